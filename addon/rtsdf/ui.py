"""RTSDF's panel in Render Properties; Blender's own panels (lights, camera,
output, world) are shown for RTSDF too."""

import bpy

ENGINE = "RTSDF"
# Built-in panels that fit RTSDF: those of the basic renderer, and EEVEE's
# light panels (energy, colour, sun angle, radius: what RTSDF reads).
EXTRA_PANELS = {"DATA_PT_EEVEE_light", "DATA_PT_EEVEE_light_distance", "DATA_PT_spot", "DATA_PT_light",
                "DATA_PT_area", "DATA_PT_context_light", "WORLD_PT_context_world", "EEVEE_WORLD_PT_surface",
                "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface"}


class RTSDF_PT_settings(bpy.types.Panel):
    bl_label = "RTSDF"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.rtsdf
        sections = (("Resolution", ("coarse_resolution", "fine_resolution", "field_budget_mb")),
                    ("Fine SDF", ("beta", "trace_band", "decay", "rays_per_texel")),
                    ("Shadows", ("shadow_method", "exact_rays", "shadow_epsilon", "shadow_max_steps", "max_step",
                                 "shadow_map_size")),
                    ("Render", ("samples", "sdf_updates", "animation_reuse", "animation_samples")),
                    ("Viewport", ("viewport_samples", "viewport_scale", "viewport_interleave", "viewport_quick_first_frame",
                                  "viewport_temporal_reuse")))
        for heading, names in sections:
            column = layout.column(align=True, heading=heading)
            for name in names:
                column.prop(settings, name)


def compatible_panels():
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is not None and ("BLENDER_RENDER" in engines or panel.__name__ in EXTRA_PANELS):
            yield panel


def register():
    bpy.utils.register_class(RTSDF_PT_settings)
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add(ENGINE)


def unregister():
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard(ENGINE)
    bpy.utils.unregister_class(RTSDF_PT_settings)
