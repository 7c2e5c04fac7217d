"""The 3D View sidebar tab "Ocean": settings, Add Ocean, Live Preview and live stats."""

import bpy

from ..projgrid_addon import bridge, effects


def active_ocean(context):
    obj = context.active_object
    if obj is not None and obj.type == "MESH" and obj.projgrid.is_ocean:
        return obj
    oceans = bridge.ocean_objects(context.scene) if context.scene else []
    return oceans[0] if oceans else None


def stats_lines(obj, scene):
    """The panel's status lines for an ocean (plain strings, so tests can check them)."""
    lines = []
    state = bridge.STATE.get(obj.name_full, {})
    if state.get("drawn_by"):
        why = ("linked from a library" if obj.library else "a library override"
               if obj.override_library else "shown more than once")
        lines.append(("LINKED", f"Drawn by our local {state['drawn_by']!r} ({why})"))
        state = {**state, **bridge.STATE.get(state["drawn_by"], {})}
    if state.get("message"):
        lines.append(("ERROR", f"Not built: {state['message']}"))
    elif state.get("hidden"):
        lines.append(("HIDE_ON", "Hidden: not rebuilt while it does not show"))
    elif "vertices" in state:
        first, count = state.get("shader_octaves", (0, 0))
        grid = state.get("grid")
        efficiency = grid.efficiency if grid is not None else 0.0  # computed on first draw
        lines += [
            ("MESH_GRID", f"Vertices: {state['vertices']:,}"),
            ("RESTRICT_VIEW_OFF", f"Vertex efficiency: {efficiency:.0%}"),
            ("TIME", f"Last rebuild: {state['ms']:.2f} ms"),
            ("SHADING_TEXTURE", f"Octaves in the shader: {count} (from {first})"),
        ]
    if state.get("warning"):
        lines.append(("ERROR", f"Flat: {state['warning']}"))
    if not scene.render.use_lock_interface:
        lines.append(("LOCKED", "Lock Interface is off: renders need it (Render > Lock "
                      "Interface), since the ocean is rebuilt while rendering"))
    return lines


def effect_lines(obj):
    """(effect, mode property, "on: reason" or "off: reason") for the last built frame."""
    decisions = bridge.STATE.get(obj.name_full, {}).get("effects") or {}
    lines = []
    for effect in effects.EFFECTS:
        on, reason = decisions.get(effect, (False, "not built yet"))
        lines.append((effect, f"{'on' if on else 'off'}: {reason}"))
    return lines


class VIEW3D_PT_projgrid_ocean(bpy.types.Panel):
    bl_label = "Projected Grid Ocean"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Ocean"

    def draw(self, context):
        layout = self.layout
        row = layout.row(align=True)
        row.operator("projgrid.add_ocean", icon="MOD_OCEAN")
        row.operator("projgrid.live_preview", icon="PLAY")
        obj = active_ocean(context)
        if obj is None:
            layout.label(text="No ocean in this scene", icon="INFO")
            return
        s = obj.projgrid
        layout.label(text=obj.name, icon="OBJECT_DATA")
        col = layout.column(align=True)
        col.prop(s, "amplitude")
        col.prop(s, "wave_scale")
        col.prop(s, "octaves")
        col.prop(s, "roughness")
        col.prop(s, "speed")
        col.prop(s, "seed")
        layout.prop(s, "projector_elevation")
        layout.prop(s, "noise")
        col = layout.column(align=True)
        col.label(text="Viewport grid")
        col.prop(s, "resolution_x", text="X")
        col.prop(s, "resolution_y", text="Y")
        col = layout.column(align=True)
        col.label(text="Render grid")
        col.prop(s, "render_resolution_x", text="X")
        col.prop(s, "render_resolution_y", text="Y")
        layout.prop(s, "wind_speed")
        box = layout.box()
        box.label(text="Effects", icon="SHADING_RENDERED")
        for effect, text in effect_lines(obj):
            col = box.column(align=True)
            col.prop(s, effect)
            col.label(text=text)
        box = layout.box()
        for icon, text in stats_lines(obj, context.scene):
            box.label(text=text, icon=icon)
