"""Quality presets (Render Properties > Sampling, the preset menu in its
header): Draft, Preview and Final, each a set of scene.rtsdf settings.
bench/run renders each one as a row of its sweep (label "preset=NAME"), so
its place on the speed-accuracy chart is measured; the tooltips below say
what it measured. The add-on writes them as Blender preset files into the
user's presets folder (presets/rtsdf/quality) when it is enabled."""

import os

SUBDIR = os.path.join("rtsdf", "quality")

# What each preset sets (scene.rtsdf names, which are the native settings' names too).
PRESETS = {
    "Draft": {"coarse_resolution": 32, "fine_resolution": 64, "exact_rays": 0, "samples": 6, "viewport_samples": 6,
              "viewport_interleave": 4},
    "Preview": {"coarse_resolution": 64, "fine_resolution": 96, "exact_rays": 0, "samples": 6, "viewport_samples": 16,
                "viewport_interleave": 4},
    "Final": {"coarse_resolution": 64, "fine_resolution": 96, "exact_rays": 4, "samples": 16, "viewport_samples": 16,
              "viewport_interleave": 4},
}


# What bench/run measured of each (the tooltips in the preset menu).
NOTES = {
    "Draft": "Coarse fields (32/64 voxels), no exact rays, 6 samples. bench/run: on the speed-accuracy front on 2 of "
             "12 scenes (simple ones: grazing, sphere_plane); elsewhere no faster than Preview, since shading, not "
             "the fields, dominates a frame there",
    "Preview": "The paper's method alone: fields of 64/96 voxels, no exact rays (no ray noise), 6 samples. bench/run: "
               "on the speed-accuracy front on 1 of 12 scenes; elsewhere Final or the viewport's interleaved rows "
               "do better for the time",
    "Final": "Fields of 64/96 voxels, 4 exact rays where the field is unsure, 16 samples. bench/run: on the "
             "speed-accuracy front on all 12 scenes, the closest to Cycles on each; below the error of EEVEE at its "
             "best (its shadow bias swept) on all 15 bench scenes, by 2-8% on the engine, the ivy and the landscape",
}


def native_settings(name):
    """A preset's render settings, as bench/run passes them to the native module (without the viewport's)."""
    return {key: value for key, value in PRESETS[name].items() if not key.startswith("viewport_")}


def preset_file_text(name):
    lines = ["import bpy", "rtsdf = bpy.context.scene.rtsdf"]
    lines += [f"rtsdf.{key} = {value!r}" for key, value in PRESETS[name].items()]
    return "\n".join(lines) + "\n"


def install(directory):
    """Writes (or refreshes) the bundled presets as preset files in `directory`."""
    os.makedirs(directory, exist_ok=True)
    for name in PRESETS:
        path = os.path.join(directory, name + ".py")
        text = preset_file_text(name)
        if os.path.exists(path):
            with open(path) as f:
                if f.read() == text:
                    continue
        with open(path, "w") as f:
            f.write(text)
