"""Draws RTSDF's Render Properties panels in a real Blender window (under
Xvfb) at the factory layout's Properties width, and applies each quality
preset. Writes OUT_DIR/panels.json and OUT_DIR/properties.png (the
Properties editor's screenshot); tests/blender/test_panels.py checks them.

xvfb-run -a -s "-screen 0 1920x1080x24" blender --factory-startup --window-geometry 0 0 1920 1080 \
    --addons rtsdf --python tests/blender/panels_driver.py -- OUT_DIR
"""
import json
import os
import sys
import traceback

import addon_utils
import blf
import bpy
import numpy as np

OUT = sys.argv[sys.argv.index("--") + 1]
os.makedirs(OUT, exist_ok=True)
results = {"errors": []}


class Recorder:
    """Stands in for a UILayout: records the label each property or label would show."""

    def __init__(self, labels, split):
        self.labels, self.use_property_split = labels, split
        self.use_property_decorate = self.active = self.enabled = True

    def column(self, **kwargs):
        return Recorder(self.labels, self.use_property_split)

    row = column

    def prop(self, data, name, text=None, **kwargs):
        rna = data.bl_rna.properties[name]
        self.labels.append({"text": rna.name if text is None else text, "boolean": rna.type == "BOOLEAN",
                            "split": self.use_property_split})

    def label(self, text="", **kwargs):
        self.labels.append({"text": text, "boolean": False, "split": False})

    def operator(self, idname, text=None, **kwargs):
        return None

    def separator(self, **kwargs):
        pass


def panel_labels(panel_class, context):
    from rtsdf import ui
    labels = []
    # (a Panel cannot be made outside Blender's drawing: draw() runs on a stand-in with the panels' helpers)
    standin = type("Standin", (ui.RenderPanel,), {})()
    standin.layout = Recorder(labels, False)
    panel_class.draw(standin, context)
    return labels


def properties_area():
    window = bpy.context.window_manager.windows[0]
    return window, max((a for a in window.screen.areas if a.type == "PROPERTIES"), key=lambda a: a.height)


def run():
    import rtsdf
    from rtsdf import presets, ui
    context = bpy.context
    context.scene.render.engine = "RTSDF"
    window, area = properties_area()
    area.spaces.active.context = "RENDER"
    results["properties_width"] = area.width
    results["ui_scale"] = context.preferences.system.ui_scale
    panels = [cls for cls in ui.classes if issubclass(cls, bpy.types.Panel) and hasattr(cls, "COMPAT_ENGINES")]
    results["panels"] = {cls.__name__: {"polls": bool(cls.poll(context)), "parent": getattr(cls, "bl_parent_id", ""),
                                        "labels": panel_labels(cls, context)} for cls in panels}
    blf.size(0, 11 * results["ui_scale"])
    for entry in results["panels"].values():
        for label in entry["labels"]:
            label["width"] = blf.dimensions(0, label["text"])[0]

    # Each preset as the menu applies it.
    directory = bpy.utils.user_resource("SCRIPTS", path=os.path.join("presets", presets.SUBDIR))
    results["presets"] = {}
    for name, values in presets.PRESETS.items():
        for key in values:  # (away from every preset's value first)
            prop = context.scene.rtsdf.bl_rna.properties[key]
            setattr(context.scene.rtsdf, key, prop.hard_max if prop.type == "INT" else prop.default)
        with context.temp_override(window=window, area=area):
            bpy.ops.render.rtsdf_quality_preset(filepath=os.path.join(directory, name + ".py"),
                                                menu_idname="RTSDF_PT_quality_presets")
        results["presets"][name] = {key: [getattr(context.scene.rtsdf, key), value] for key, value in values.items()}
        description = ui.RTSDF_OT_quality_preset.description(context, type("P", (), {
            "filepath": os.path.join(directory, name + ".py")})())
        results["presets"][name]["tooltip"] = description

    # The panels as Blender draws them.
    area.tag_redraw()
    bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=2)
    shot = os.path.join(OUT, "window.png")
    with context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot(filepath=shot)
    image = bpy.data.images.load(shot)
    pixels = np.array(image.pixels[:], np.float32).reshape(image.size[1], image.size[0], image.channels)
    crop = pixels[area.y:area.y + area.height, area.x:area.x + area.width, :3]
    results["properties_std"] = float(crop.std())
    out = bpy.data.images.new("properties", area.width, area.height)
    out.pixels.foreach_set(np.concatenate([crop, np.ones(crop.shape[:2] + (1,), np.float32)], -1).ravel())
    out.filepath_raw = os.path.join(OUT, "properties.png")
    out.file_format = "PNG"
    out.save()


def finish():
    try:
        run()
    except Exception:
        results["errors"].append(traceback.format_exc())
    with open(os.path.join(OUT, "panels.json"), "w") as f:
        json.dump(results, f, indent=1)
    bpy.ops.wm.quit_blender()


# After the window has drawn once.
bpy.app.timers.register(finish, first_interval=1.0)
