"""RTSDF: real-time signed distance field soft shadows for Blender (Vulkan)."""

bl_info = {
    "name": "RTSDF",
    "author": "RTSDF developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Preferences > Add-ons > RTSDF",
    "description": "Signed distance fields generated in real time on Vulkan, for soft shadows",
    "category": "Render",
}

import bpy

from . import native


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


classes = (RTSDF_AddonPreferences,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
