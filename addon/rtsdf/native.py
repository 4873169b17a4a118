"""Loads the native module next to this file and turns its failures into
messages for the UI, so that a missing driver never breaks Blender."""
import os

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


def default_field_store_directory():
    """The user's cache directory (XDG_CACHE_HOME, else ~/.cache)/rtsdf/fields."""
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "rtsdf", "fields")


def field_store_directory(preferences):
    """Where the session keeps refined fields on disk, or "" for nowhere.
    RTSDF_FIELD_STORE in the environment overrides the preferences: a
    directory, or "off" (benchmarks that time a cold build set it)."""
    forced = os.environ.get("RTSDF_FIELD_STORE")
    if forced is not None:
        return "" if forced.strip().lower() in ("", "off", "0") else forced
    if preferences is None or not preferences.keep_fields_on_disk:
        return ""
    if not preferences.field_store_directory:
        return default_field_store_directory()
    import bpy  # (for a path relative to the .blend, "//")
    return bpy.path.abspath(preferences.field_store_directory)


def use_field_store(session, preferences):
    """Points the session's field store where the preferences say. Returns
    None, or why the fields stay in memory only (a warning for the user:
    nothing else is lost)."""
    directory = field_store_directory(preferences)
    capacity = preferences.field_store_mb if preferences is not None else 2048
    module, _ = load()
    try:
        session.set_field_store(directory, capacity)
    except module.Error as e:
        session.set_field_store("", capacity)
        return f"fields are kept in memory only: {e}"
    return None


FIELD_FILE_SUFFIX = ".rtsdf-field"  # (native/field_store.cpp names its files so)


def _field_files(directory):
    try:
        return [entry for entry in os.scandir(directory) if entry.name.endswith(FIELD_FILE_SUFFIX)]
    except OSError:
        return []


def field_store_usage(directory):
    """(fields, MB) kept in `directory`."""
    total = 0
    files = _field_files(directory)
    for entry in files:
        try:
            total += entry.stat().st_size
        except OSError:  # (removed meanwhile by another Blender)
            pass
    return len(files), total / (1 << 20)


def clear_field_store(directory):
    """Deletes the fields kept in `directory`; returns how many."""
    removed = 0
    for entry in _field_files(directory):
        try:
            os.remove(entry.path)
            removed += 1
        except OSError:
            pass
    return removed
