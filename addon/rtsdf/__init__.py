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


modules = (properties, engine, ui, compare)


def register():
    bpy.utils.register_class(RTSDF_AddonPreferences)
    for module in modules:
        module.register()


def unregister():
    for module in reversed(modules):
        module.unregister()
    bpy.utils.unregister_class(RTSDF_AddonPreferences)
