// Visibility shared from the quad pass (quad_visibility.comp): a pixel on
// the same surface as the samples of the quads around it takes their value;
// the others are listed (list_for_next_pass) for the fill pass (kShadeFill),
// which marches them.
// Needs shade_inputs.glsl.h (quad_samples, quad_lights, fill list, G-buffer).

// This pixel's share of the world light (light < 0) or of light `light`
// from the quad pass's samples of the four quads around it that lie on its
// surface (close normal and plane), weighted bilinearly; < 0: none does.
float shared_visibility(ivec2 pixel, vec3 p, vec3 n, int light) {
  vec2 quad_position = (vec2(pixel) + 0.5) * 0.5 - 0.5;  // in quads, whose centres are at integers
  ivec2 base = ivec2(floor(quad_position));
  vec2 f = quad_position - vec2(base);
  ivec2 last = quad_grid() - 1;
  float sum = 0.0, weights = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 corner = ivec2(k & 1, k >> 1);
    ivec2 quad = clamp(base + corner, ivec2(0), last);
    vec4 sample_normal = imageLoad(quad_samples, quad);  // xyz = normal, w = world light (< 0: no sample)
    float value = light < 0 ? sample_normal.w : quad_lights[light * quad_count() + quad.x + quad_grid().x * quad.y];
    if (sample_normal.w < 0.0 || value < 0.0) continue;
    vec4 at = imageLoad(g_position, quad_sample_pixel(quad));
    if (!on_sample_surface(p, n, at.xyz, sample_normal.xyz)) continue;
    vec2 bilinear = mix(1.0 - f, f, vec2(corner));
    float w = bilinear.x * bilinear.y + 1e-3;
    sum += w * value;
    weights += w;
  }
  return weights > 0.0 ? sum / weights : -1.0;
}

