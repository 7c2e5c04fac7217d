"""Projected Grid Ocean: Blender extension entry point (register and unregister only)."""

from . import operators, panels
from .projgrid_addon import bridge, handlers

# Registered in this order, unregistered in exact reverse.
modules = (bridge, operators, panels, handlers)


def register():
    for module in modules:
        module.register()


def unregister():
    for module in reversed(modules):
        module.unregister()
