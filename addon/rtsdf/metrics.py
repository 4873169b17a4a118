"""Image figures for comparing RTSDF with a reference (Cycles): numpy only
(Blender bundles no scikit-image or matplotlib), no bpy, so that the compare
operator, scripts/compare_render.py and bench/run share them. Images are
linear RGB float arrays (H, W, 3), rows top to bottom."""

import numpy as np

# Where Cycles' own visibility (its render over one with shadow casting off)
# is below this, a pixel is in the shadowed region.
SHADOWED_BELOW = 0.98
# Cycles' umbra, for the leak figure.
UMBRA_BELOW = 0.1


def to_display(linear):
    """Linear -> sRGB (for viewing and SSIM; the other figures are on linear values)."""
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def visibility(shadowed, unshadowed):
    """Share of direct light reaching each pixel, from renders with and without shadows."""
    return shadowed.mean(axis=-1) / np.maximum(unshadowed.mean(axis=-1), 1e-4)


def rmse(a, b, mask=None):
    if mask is not None:
        if not mask.any():
            return 0.0
        a, b = a[mask], b[mask]
    return float(np.sqrt(np.mean((a - b) ** 2)))


def box_mean(image, size):
    """Mean over every size x size window that fits in the image (the valid part of a box filter)."""
    summed = np.pad(np.cumsum(np.cumsum(image, axis=0), axis=1), ((1, 0), (1, 0)))
    total = summed[size:, size:] - summed[:-size, size:] - summed[size:, :-size] + summed[:-size, :-size]
    return total / (size * size)


def structural_similarity(x, y, window=7, data_range=1.0):
    """Mean SSIM (Wang et al. 2004) of two grey images, as scikit-image computes it by default: a
    7x7 uniform window, sample covariances, K1 = 0.01, K2 = 0.03, over the windows that fit."""
    x, y = x.astype(np.float64), y.astype(np.float64)
    mx, my = box_mean(x, window), box_mean(y, window)
    unbias = window * window / (window * window - 1.0)
    vx = unbias * (box_mean(x * x, window) - mx * mx)
    vy = unbias * (box_mean(y * y, window) - my * my)
    vxy = unbias * (box_mean(x * y, window) - mx * my)
    c1, c2 = (0.01 * data_range) ** 2, (0.03 * data_range) ** 2
    s = (2 * mx * my + c1) * (2 * vxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2))
    return float(s.mean())


def ssim(a, b):
    return structural_similarity(to_display(a).mean(axis=-1), to_display(b).mean(axis=-1), data_range=1.0)


def leak(image, reference, unshadowed, world, least_pixels=20):
    """Share of the reference's umbra pixels in which `image` gets more than half of the lights'
    direct light. The lights' light is the unshadowed render less the world's light alone; the
    umbra is where it counts (a quarter or more of the unshadowed light) and under UMBRA_BELOW of
    it reaches the reference. None when fewer than `least_pixels` pixels are in the umbra."""
    sky = world.mean(axis=-1)
    lights = unshadowed.mean(axis=-1) - sky
    counts = lights > 0.25 * np.maximum(unshadowed.mean(axis=-1), 1e-6)
    safe = np.maximum(lights, 1e-6)
    umbra = counts & ((reference.mean(axis=-1) - sky) / safe < UMBRA_BELOW)
    if umbra.sum() < least_pixels:
        return None
    return float(np.mean((image.mean(axis=-1)[umbra] - sky[umbra]) / safe[umbra] > 0.5))


def flicker(frames, mask=None):
    """Mean absolute change between consecutive frames (linear RGB) of a still
    scene, or over the pixels `mask` (H, W) picks: those nothing moves over."""
    if len(frames) < 2:
        return 0.0
    pick = (lambda change: change[mask]) if mask is not None else (lambda change: change)
    return float(np.mean([pick(np.abs(b - a)).mean() for a, b in zip(frames[:-1], frames[1:])]))


def compare(image, reference, reference_unshadowed):
    """The figures of `image` against `reference` (RMSE, SSIM, shadow-region RMSE)."""
    shadowed = visibility(reference, reference_unshadowed) < SHADOWED_BELOW
    return {"rmse": rmse(image, reference), "ssim": ssim(image, reference),
            "shadow_rmse": rmse(image, reference, shadowed), "shadow_pixels": int(shadowed.sum())}


# Matplotlib's "inferno" at nine even stops, for the difference heat map.
INFERNO = np.array([[0.001, 0.000, 0.014], [0.129, 0.047, 0.291], [0.342, 0.062, 0.429], [0.541, 0.135, 0.415],
                    [0.736, 0.216, 0.330], [0.894, 0.353, 0.194], [0.978, 0.558, 0.035], [0.975, 0.798, 0.206],
                    [0.988, 0.998, 0.645]])


def heat(values):
    """values in [0, 1] -> RGB on the inferno ramp."""
    position = np.clip(values, 0.0, 1.0) * (len(INFERNO) - 1)
    return np.stack([np.interp(position, np.arange(len(INFERNO)), INFERNO[:, c]) for c in range(3)], axis=-1)


def side_by_side(image, reference, vmax=0.25):
    """image | reference | heat map of |image - reference| as one display-ready RGB array."""
    difference = np.abs(image - reference).mean(axis=-1) / vmax
    return np.concatenate([to_display(image), to_display(reference), heat(difference)], axis=1).astype(np.float32)
