"""RTSDF: real-time signed distance field soft shadows for Blender (Vulkan)."""

bl_info = {
    "name": "RTSDF",
    "author": "RTSDF developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > RTSDF",
    "description": "Signed distance fields generated in real time on Vulkan, for soft shadows",
    "category": "Render",
}

import bpy

from . import compare, engine, native, properties, ui


class RTSDF_AddonPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    keep_fields_on_disk: bpy.props.BoolProperty(
        name="Keep Fields on Disk", default=True,
        description="Keep each mesh's refined distance field on disk, so that later renders and viewports, "
                    "in this Blender or the next, take it instead of tracing it again (a mesh that deforms "
                    "is traced every frame either way)")
    field_store_directory: bpy.props.StringProperty(
        name="Directory", subtype="DIR_PATH", default="",
        description="Where the fields are kept; empty: the user's cache directory (~/.cache/rtsdf/fields)")
    field_store_mb: bpy.props.IntProperty(
        name="Disk Space (MB)", default=2048, min=16, max=1 << 20,
        description="The most the kept fields take on disk; the least recently used go first")

    def draw(self, context):
        layout = self.layout
        module, error = native.load()
        if module is None:
            layout.label(text=f"Native module unavailable: {error}", icon="ERROR")
            return
        layout.label(text=f"Native core {module.__version__}")
        device, error = native.device()
        if device is None:
            layout.label(text=error, icon="ERROR")
        else:
            layout.label(text=f"Vulkan device: {device['name']} ({device['type']}, Vulkan {device['api_version']})")
        layout.prop(self, "keep_fields_on_disk")
        column = layout.column()
        column.active = self.keep_fields_on_disk
        column.prop(self, "field_store_directory")
        column.prop(self, "field_store_mb")
        directory = native.field_store_directory(self)
        if directory:
            files, megabytes = native.field_store_usage(directory)
            row = column.row()
            row.label(text=f"{directory}: {files} fields, {megabytes:.1f} MB")
            row.operator("rtsdf.clear_field_store", text="Clear")


class RTSDF_OT_clear_field_store(bpy.types.Operator):
    """Deletes the fields kept on disk (each mesh's next render traces its field again)"""
    bl_idname = "rtsdf.clear_field_store"
    bl_label = "Clear Kept Fields"

    def execute(self, context):
        addon = context.preferences.addons.get(__package__)
        directory = native.field_store_directory(addon.preferences if addon else None)
        removed = native.clear_field_store(directory) if directory else 0
        self.report({"INFO"}, f"RTSDF: {removed} kept fields deleted")
        return {"FINISHED"}


modules = (properties, engine, ui, compare)


def register():
    bpy.utils.register_class(RTSDF_AddonPreferences)
    bpy.utils.register_class(RTSDF_OT_clear_field_store)
    for module in modules:
        module.register()


def unregister():
    for module in reversed(modules):
        module.unregister()
    bpy.utils.unregister_class(RTSDF_OT_clear_field_store)
    bpy.utils.unregister_class(RTSDF_AddonPreferences)
