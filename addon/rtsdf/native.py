"""Loads the native module next to this file and turns its failures into
messages for the UI, so that a missing driver never breaks Blender."""

_module = None
_error = None
_device = None
_session = None


class Unavailable(Exception):
    """The native module or its Vulkan device cannot be had; the message says why."""


def errors():
    """The exceptions whose message is for the user: Unavailable and the native
    core's rtsdf_native.Error (bad input, no device, out of memory), not
    Blender's own RuntimeErrors."""
    module, _ = load()
    return (Unavailable,) if module is None else (Unavailable, module.Error)


def load():
    """Returns (module, None) or (None, reason)."""
    global _module, _error
    if _module is None and _error is None:
        try:
            from . import rtsdf_native as module
            _module = module
        except ImportError as e:  # built for another Python, or not built
            _error = f"{e} (run scripts/setup.sh)"
    return _module, _error


def device():
    """Returns (info dict, None) or (None, reason), asking the driver once."""
    global _device
    module, error = load()
    if module is None:
        return None, error
    if _device is None:
        try:
            _device = module.device_info()
        except module.Error as e:
            return None, str(e)
    return _device, None


def session():
    """Returns (Session, None) or (None, reason). One per Blender process: the
    Vulkan device and the renderer's resources live on between renders."""
    global _session
    module, error = load()
    if module is None:
        return None, error
    if _session is None:
        try:
            _session = module.Session()
        except module.Error as e:
            return None, str(e)
    return _session, None
