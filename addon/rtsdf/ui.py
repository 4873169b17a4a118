"""RTSDF's panels in Render Properties, laid out as Blender's own engines lay
out theirs: Sampling (render and viewport, with the quality presets in its
header), Shadows, Distance Fields, Advanced (folded) and Compare with
Cycles. Blender's own panels (lights, camera, output, world) are shown for
RTSDF too."""

import os

import bpy
from bl_operators.presets import AddPresetBase
from bl_ui.utils import PresetPanel

from . import presets

ENGINE = "RTSDF"
# Built-in panels that fit RTSDF: those of the basic renderer, and EEVEE's
# light panels (energy, colour, sun angle, radius: what RTSDF reads).
EXTRA_PANELS = {"DATA_PT_EEVEE_light", "DATA_PT_EEVEE_light_distance", "DATA_PT_spot", "DATA_PT_light",
                "DATA_PT_area", "DATA_PT_context_light", "WORLD_PT_context_world", "EEVEE_WORLD_PT_surface",
                "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface"}
# The basic renderer's panels that RTSDF does not read or that repeat EEVEE's
# (its own Light panel beside EEVEE's made two), and light probes (none here).
EXCLUDED_PANELS = {"DATA_PT_light", "NODE_DATA_PT_light", "DATA_PT_falloff_curve"}
SDF_METHODS = {"rtsdf", "rtsdf_world", "rt_only"}
SHADOW_MAP_METHODS = {"csm_evsm", "csm_jitter"}


class RTSDF_OT_quality_preset(bpy.types.Operator):
    """Apply an RTSDF quality preset"""
    bl_idname = "render.rtsdf_quality_preset"
    bl_label = "Apply Quality Preset"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    menu_idname: bpy.props.StringProperty(options={"SKIP_SAVE"})

    @classmethod
    def description(cls, context, properties):
        # The bundled presets say what bench/run measured of them.
        name = os.path.splitext(os.path.basename(properties.filepath))[0]
        return presets.NOTES.get(name, "Apply this RTSDF quality preset")

    def execute(self, context):
        return bpy.ops.script.execute_preset(filepath=self.filepath, menu_idname=self.menu_idname)


class RTSDF_PT_quality_presets(PresetPanel, bpy.types.Panel):
    bl_label = "Quality Presets"
    preset_subdir = presets.SUBDIR
    preset_operator = "render.rtsdf_quality_preset"
    preset_add_operator = "render.rtsdf_quality_preset_add"


class RTSDF_OT_quality_preset_add(AddPresetBase, bpy.types.Operator):
    """Add or remove an RTSDF quality preset"""
    bl_idname = "render.rtsdf_quality_preset_add"
    bl_label = "Add Quality Preset"
    preset_menu = "RTSDF_PT_quality_presets"
    preset_defines = ["rtsdf = bpy.context.scene.rtsdf"]
    preset_values = [f"rtsdf.{name}" for name in presets.PRESETS["Final"]]
    preset_subdir = presets.SUBDIR


class RenderPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def split_layout(self):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        return layout


class RTSDF_PT_sampling(RenderPanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw_header_preset(self, context):
        RTSDF_PT_quality_presets.draw_panel_header(self.layout)

    def draw(self, context):
        pass


class RTSDF_PT_sampling_render(RenderPanel, bpy.types.Panel):
    bl_label = "Render"
    bl_parent_id = "RTSDF_PT_sampling"

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        layout.prop(settings, "samples", text="Samples")
        layout.prop(settings, "noise_threshold", text="Noise Threshold")
        column = layout.column(heading="Animation")
        column.prop(settings, "animation_reuse", text="Reuse Between Frames")
        row = column.row()
        row.active = settings.animation_reuse
        row.prop(settings, "animation_samples", text="Frame Samples")


class RTSDF_PT_sampling_viewport(RenderPanel, bpy.types.Panel):
    bl_label = "Viewport"
    bl_parent_id = "RTSDF_PT_sampling"

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        layout.prop(settings, "viewport_samples", text="Samples")
        layout.prop(settings, "viewport_scale", text="Resolution Scale")
        column = layout.column(heading="While Playing")
        column.prop(settings, "viewport_temporal_reuse", text="Temporal Reuse")
        column.prop(settings, "viewport_quick_first_frame", text="Quick First Frame")


class RTSDF_PT_shadows(RenderPanel, bpy.types.Panel):
    bl_label = "Shadows"

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        layout.prop(settings, "shadow_method", text="Method")
        row = layout.row()
        row.active = settings.shadow_method in SDF_METHODS
        row.prop(settings, "exact_rays", text="Exact Rays")
        row = layout.row()
        row.active = settings.shadow_method in SDF_METHODS and settings.exact_rays > 0
        row.prop(settings, "short_history_rays", text="While Playing")
        row = layout.row()
        row.active = settings.shadow_method in SHADOW_MAP_METHODS
        row.prop(settings, "shadow_map_size", text="Map Size")


class RTSDF_PT_fields(RenderPanel, bpy.types.Panel):
    bl_label = "Distance Fields"

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        active = settings.shadow_method in SDF_METHODS | {"jfa_only"}
        column = layout.column(align=True, heading="Resolution")
        column.active = active
        column.prop(settings, "coarse_resolution", text="Coarse (voxels)")
        column.prop(settings, "fine_resolution", text="Fine (voxels)")
        column = layout.column()
        column.active = active
        column.prop(settings, "field_budget_mb", text="Budget (MB)")
        column.prop(settings, "trace_band", text="Band (voxels)")
        column.prop(settings, "viewport_interleave", text="Interleave")


class RTSDF_PT_advanced(RenderPanel, bpy.types.Panel):
    bl_label = "Advanced"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        column = layout.column(align=True, heading="Fine Field")
        column.prop(settings, "decay", text="Decay")
        column.prop(settings, "rays_per_texel", text="Rays per Texel")
        column.prop(settings, "sdf_updates", text="Render Updates")
        column.prop(settings, "beta", text="Beta (voxels)")
        column = layout.column(align=True, heading="Shadow March")
        column.prop(settings, "shadow_epsilon", text="Epsilon (voxels)")
        column.prop(settings, "max_step", text="Max Step (voxels)")
        column.prop(settings, "shadow_max_steps", text="Steps")


class RTSDF_PT_field_view(RenderPanel, bpy.types.Panel):
    bl_label = "Field View"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.split_layout()
        settings = context.scene.rtsdf
        layout.prop(settings, "field_view", text="View")
        row = layout.row()
        row.active = settings.field_view == "distance_slice"
        row.prop(settings, "field_view_height", text="Slice Height")


class RTSDF_PT_object_visibility(RenderPanel, bpy.types.Panel):
    """Object Properties > Visibility > Ray Visibility, as Cycles has it (its
    own panel shows for Cycles only): what the object is seen by."""
    bl_label = "Ray Visibility"
    bl_context = "object"
    bl_parent_id = "OBJECT_PT_visibility"

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES and context.object is not None

    def draw(self, context):
        column = self.split_layout().column(heading="Visible To")
        column.prop(context.object, "visible_camera", text="Camera")
        column.prop(context.object, "visible_shadow", text="Shadow")


class RTSDF_PT_compare(RenderPanel, bpy.types.Panel):
    bl_label = "Compare with Cycles"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        layout.operator("render.rtsdf_compare", icon="IMAGE_REFERENCE")
        figures = context.scene.get("rtsdf_compare")
        if not figures:
            layout.label(text="Not compared yet")
            return
        column = layout.column(align=True)
        column.label(text=f"Shadow RMSE {figures['shadow_rmse']:.4f}, RMSE {figures['rmse']:.4f}")
        column.label(text=f"SSIM {figures['ssim']:.3f}")
        column.label(text=f"RTSDF {figures['rtsdf_seconds']:.2f} s, Cycles {figures['cycles_seconds']:.2f} s "
                          f"({figures['cycles_samples']} samples)")


classes = (RTSDF_OT_quality_preset, RTSDF_PT_quality_presets, RTSDF_OT_quality_preset_add, RTSDF_PT_sampling, RTSDF_PT_sampling_render,
           RTSDF_PT_sampling_viewport, RTSDF_PT_shadows, RTSDF_PT_fields, RTSDF_PT_advanced, RTSDF_PT_field_view,
           RTSDF_PT_compare, RTSDF_PT_object_visibility)


def compatible_panels():
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        name = panel.__name__
        if name in EXCLUDED_PANELS or name.startswith("DATA_PT_lightprobe"):
            continue
        if engines is not None and ("BLENDER_RENDER" in engines or name in EXTRA_PANELS):
            yield panel


def install_presets():
    """The bundled quality presets, where Blender's preset menu finds them."""
    directory = bpy.utils.user_resource("SCRIPTS", path=os.path.join("presets", presets.SUBDIR), create=True)
    try:
        presets.install(directory)
    except OSError as e:
        print(f"RTSDF: could not write the quality presets to {directory}: {e}")


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    install_presets()
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.add(ENGINE)


def unregister():
    for panel in compatible_panels():
        panel.COMPAT_ENGINES.discard(ENGINE)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
