"""Projected Grid Ocean: Blender extension entry point (register and unregister only).

The submodules are imported in register(), not at import time: pytest imports this file as the
package of the repository root, and the core's tests must run without bpy.
"""


def _modules():
    """Registered in this order, unregistered in exact reverse."""
    from . import operators, panels
    from .operators.bridge import float_settings, handlers, settings

    return (settings, float_settings, operators, panels, handlers)


def register():
    for module in _modules():
        module.register()


def unregister():
    for module in reversed(_modules()):
        module.unregister()
