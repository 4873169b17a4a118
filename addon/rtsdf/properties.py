"""RTSDF settings, stored on the scene as scene.rtsdf (names as in the native core)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty


def redraw_viewports(self, context):
    """A setting that changes what the viewport draws: redraw the 3D views now (a scene property
    changed from the panel or a script does not by itself)."""
    for window in getattr(context.window_manager, "windows", []):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


class RTSDFSettings(bpy.types.PropertyGroup):
    shadow_method: EnumProperty(
        name="Shadow Method", default="rtsdf",
        items=(("rtsdf", "RTSDF",
                "The paper's fields (jump-flooded coarse SDF, ray-traced fine SDF near surfaces), one per mesh in its "
                "own space and shared by its instances: moving objects cost no SDF work"),
               ("rtsdf_world", "RTSDF (whole scene)",
                "The paper as published: one field of the whole scene, rebuilt whenever anything moves"),
               ("rt_only", "RT only", "Baseline: the fine SDF ray traced at every texel of its grid, every frame"),
               ("jfa_only", "JFA only", "Baseline: shadows marched through the jump-flooded coarse SDF alone"),
               ("csm_evsm", "CSM + EVSM",
                "Baseline: cascaded shadow maps filtered as exponential variance shadow maps, as wide as the "
                "penumbra a blocker search finds (PCSS)"),
               ("csm_jitter", "CSM Jittered",
                "Baseline: sharp cascaded shadow maps whose origin moves over the light every sample, as EEVEE's "
                "soft shadows do; converges towards the true penumbra over the samples"),
               ("raytraced", "Ray Traced",
                "Reference: exact shadow rays through the scene's BVHs towards a random point of each light, "
                "averaging to the exact soft shadow over the samples (slow)")),
        description="Where shadows come from; all methods share the same shading")
    exact_rays: IntProperty(
        name="Exact Rays", default=4, min=0, max=64,
        description="RTSDF methods: where the field cannot tell lit from shadowed with Epsilon to spare (penumbrae, "
                    "contact, leaf cards and walls thinner than a voxel), this many rays per light and sample through "
                    "the meshes decide instead: shadows converge to the exact ones over the samples. 0: the field's "
                    "cone estimate everywhere, as in the paper (no noise while playing, less accurate)")
    short_history_rays: IntProperty(
        name="Exact Rays While Playing", default=4, min=1, max=16,
        description="In the frame after a change (playing, dragging, an animation render that carries history), "
                    "Exact Rays are this many times as many where a moved shadow falls on a still surface or a "
                    "surface was uncovered: there that one frame is most of what shows. Higher: smoother moving "
                    "shadows; 1: faster playback where exact rays are many and costly (dense CAD)")
    shadow_map_size: IntProperty(
        name="Shadow Map Size", default=1024, min=64, max=4096,
        description="Shadow-map methods: texels per side of each cascade (sun), spot light view or cube face. "
                    "Larger: sharper, better placed shadows; each doubling costs 4x the map's memory and raster time")
    coarse_resolution: IntProperty(
        name="Coarse", default=64, min=8, max=512,
        description="Voxels on the longest axis of the coarse (jump-flooded) SDF: of each mesh's own field (RTSDF), "
                    "or of the whole scene's. Higher: a tighter band to trace and longer safe steps; costs memory "
                    "and jump-flood time (cubic)")
    fine_resolution: IntProperty(
        name="Fine", default=128, min=16, max=1024,
        description="Voxels on the longest axis of the fine (ray-traced) SDF, of each mesh's own field (RTSDF: up "
                    "to 1.5x as many, and 1.5x the coarse ones, for a rigid mesh whose parts are thinner than "
                    "its voxel) or of the whole scene's; at least the coarse resolution. Higher: thin parts and "
                    "contact shadows resolved; the field's build time and memory grow with its surface (square)")
    field_budget_mb: FloatProperty(
        name="Field Memory (MB)", default=1024.0, min=16.0, max=65536.0,
        description="RTSDF: device memory for all meshes' fields; when they need more, every mesh's resolution is "
                    "lowered alike (reported in the stats)")
    beta: FloatProperty(
        name="Beta", default=0.5, min=0.0, max=4.0,
        description="In coarse voxels, subtracted from the coarse distance: thickens surfaces so the band to "
                    "trace holds them. Larger: safer for thin parts, a wider band to trace")
    trace_band: FloatProperty(
        name="Band", default=2.0, min=0.5, max=16.0,
        description="d, in coarse voxels: fine texels this close to a surface are ray traced. Wider: more of "
                    "the field exact (soft penumbrae far from casters); more texels to trace")
    decay: FloatProperty(
        name="Decay", default=0.9, min=0.0, max=0.99,
        description="Alpha: weight of the previous frame's distance to thin pieces (sheets, leaf cards) in the fine "
                    "SDF. Higher: their slabs hold with less noise; a moving thin piece's slab lags it longer. "
                    "Other texels keep their nearest triangle and measure it again each frame")
    rays_per_texel: IntProperty(
        name="Rays", default=8, min=1, max=64,
        description="Rays cast from each traced fine texel per frame. More: a field closer to exact in fewer "
                    "frames; each frame costs that much more")
    shadow_epsilon: FloatProperty(
        name="Epsilon", default=1.0, min=0.25, max=4.0,
        description="In fine voxels: how close the shadow march must come to a surface to call it blocked. "
                    "Larger: fewer leaks through thin parts, but shadows spread and contact gaps close")
    shadow_max_steps: IntProperty(
        name="Steps", default=96, min=8, max=1024,
        description="Step limit of the shadow march. More: long rays past many objects reach the light instead of "
                    "stopping short (an unfinished march counts as lit); each step costs shading time")
    max_step: FloatProperty(
        name="Max Step", default=4.0, min=0.5, max=32.0,
        description="Longest step of the shadow march, in fine voxels (shorter removes banding, costs more)")
    samples: IntProperty(
        name="Samples", default=16, min=1, max=1024,
        description="Accumulation frames for a final render, each with its own sub-pixel and shadow jitter. More: "
                    "smoother penumbrae and edges; the render takes that many frames")
    noise_threshold: FloatProperty(
        name="Noise Threshold", default=0.03, min=0.0, max=1.0, precision=3,
        description="Adaptive sampling, in final renders and the viewport: once half the samples are in, a tile of "
                    "pixels whose samples agree (their spread below this share of each pixel's brightness) takes "
                    "no more, and the render ends once every tile has. Lower: fewer pixels stop early; 0: every "
                    "pixel takes every sample",
        update=redraw_viewports)
    animation_reuse: BoolProperty(
        name="Reuse Between Frames", default=False,
        description="Animation renders with Persistent Data (Performance panel): each frame renders Animation "
                    "Samples and carries the earlier frames' samples over where they still show the same surface "
                    "(reprojected and variance-clipped, as the viewport's Temporal Reuse), standing in for the rest "
                    "of Samples. Faster; where shadows move, fewer samples. Off: every frame renders in full")
    animation_samples: IntProperty(
        name="Animation Samples", default=4, min=1, max=1024,
        description="Accumulation frames per frame of an animation render with Reuse Between Frames")
    sdf_updates: IntProperty(
        name="SDF Updates", default=0, min=0, max=4096,
        description="Fine-SDF updates in a final render, one in each of the first accumulation frames "
                    "(0: every frame for the whole-scene methods, four passes over the band for RTSDF's fields; "
                    "as bench/run measures; a still mesh's field retraces only what still improves, and stops "
                    "once nothing does). Fewer: a faster render; a still frame's field is close to converged "
                    "after a few")

    viewport_samples: IntProperty(
        name="Viewport Samples", default=16, min=1, max=1024,
        description="Accumulation frames in the viewport; after these the viewport stops working until something "
                    "changes. More: a cleaner still image; the CPU or GPU stays busy longer")
    viewport_scale: FloatProperty(
        name="Viewport Scale", default=0.5, min=0.1, max=1.0, subtype="FACTOR",
        description="Viewport rendering resolution relative to the region (rendered smaller, then scaled up). "
                    "Lower: faster frames while playing; softer image")
    viewport_interleave: IntProperty(
        name="Viewport Interleave", default=4, min=1, max=16,
        description="Each fine-SDF texel is traced every K-th viewport frame: K times less work per frame, "
                    "K times as many frames to converge")
    viewport_quick_first_frame: BoolProperty(
        name="Quick First Frame", default=True,
        description="The frame after a change marches the lights' shadows at one pixel of each 2x2 quad and "
                    "shares them along each surface: about half the shading cost while playing or dragging. "
                    "The frames after it march every pixel")
    viewport_temporal_reuse: BoolProperty(
        name="Temporal Reuse", default=True,
        description="While playing or dragging, each frame reprojects the previous frames' shadows along the "
                    "objects' and camera's motion (variance-clipped, dropped where a surface was hidden or a moved "
                    "caster crosses the light path) instead of starting from one noisy sample. Deforming meshes "
                    "reproject with their object's motion only")

    field_view: EnumProperty(
        name="Field View", default="none",
        items=(("none", "Shaded", "The rendered image"),
               ("distance_slice", "Distance Slice",
                "A section at Slice Height (what is in front of it cut away): the fields' signed distance on that "
                "horizontal plane as a heat map, blue inside, a line every voxel, tinted cyan where a brick of the "
                "fine field is stored"),
               ("march_steps", "March Steps",
                "The fields' surfaces as the shadow march sees them, coloured by the steps it takes to reach them "
                "(where shadows cost the most)"),
               ("field_resolution", "Field Resolution",
                "Each surface by its field's voxel size against the pixel's size there: blue finer than a pixel, "
                "yellow coarser (where shadows lose detail); grey: in no field"),
               ("exact_rays", "Exact Rays",
                "The image, magenta where the field could not tell lit from shadowed and rays were traced")),
        description="A view of the distance fields in place of the image, to see why a shadow leaks or smears "
                    "(RTSDF methods)", update=redraw_viewports)
    field_view_height: FloatProperty(
        name="Slice Height", default=0.0, subtype="DISTANCE", unit="LENGTH",
        description="World height (Z) of the Distance Slice view's plane", update=redraw_viewports)

    def as_dict(self):
        settings = {name: getattr(self, name) for name in self.__annotations__}
        # The pixel filter is the scene's (Film > Filter Size), as Cycles' and EEVEE's are.
        settings["filter_width"] = self.id_data.render.filter_size
        return settings


classes = (RTSDFSettings,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.rtsdf = bpy.props.PointerProperty(type=RTSDFSettings)


def unregister():
    del bpy.types.Scene.rtsdf
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
