"""The 3D View sidebar tab "Ocean": Add Ocean and Live Preview, then sub-panels for the waves,
the grids, the look, the effects and the live status, as Blender's own panels lay out
settings."""

import bpy

from ..operators.bridge import baked, frame, scene
from ..operators.bridge.state import RUNTIME
from ..projgrid_addon import effects, sea_states

active_ocean = scene.active_ocean


def stats_lines(obj, the_scene):
    """The panel's status lines for an ocean (plain strings, so tests can check them)."""
    lines = bake_lines(obj, the_scene)
    if lines:
        return lines
    own = RUNTIME.peek(obj)
    if own is not None and own.drawn_by:
        why = ("linked from a library" if obj.library else "a library override"
               if obj.override_library else "shown more than once")
        lines.append(("LINKED", f"Drawn by our local {own.drawn_by!r} ({why})"))
    state = frame.surface_state(obj)
    if state is not None and state.message:
        lines.append(("ERROR", f"Not built: {state.message}"))
    elif state is not None and state.hidden:
        lines.append(("HIDE_ON", "Hidden: not rebuilt while it does not show"))
    elif state is not None and state.grid is not None:
        first, count = state.grid.shader_octaves
        lines += [
            ("MESH_GRID", f"Vertices: {state.vertices:,}"),
            ("RESTRICT_VIEW_OFF", f"Vertex efficiency: {state.grid.efficiency:.0%}"),
            ("TIME", f"Last rebuild: {state.ms:.2f} ms"),
            ("SHADING_TEXTURE", f"Octaves in the shader: {count} (from {first})"),
        ]
    if state is not None and state.warning:
        lines.append(("ERROR", f"Flat: {state.warning}"))
    note = frame.cycles_note(the_scene, obj)
    if note:
        lines.append(("ERROR", note))
    if not the_scene.render.use_lock_interface:
        lines.append(("LOCKED", "Lock Interface is off: renders need it (Render > Lock "
                      "Interface), since the ocean is rebuilt while rendering"))
    return lines


def bake_lines(obj, the_scene):
    """The panel's lines about an ocean's bake (none while it is live)."""
    mod = baked.cache_modifier(obj)
    if mod is None:
        return []
    start, end = obj.projgrid.bake_frames
    path = mod.cache_file.filepath if mod.cache_file is not None else "?"
    lines = [("FILE_CACHE", f"Plays its bake: frames {start}-{end} for camera "
                            f"{obj.projgrid.bake_camera!r}"),
             ("FILE", path)]
    why = baked.stale(the_scene, obj)
    if why:
        lines.append(("ERROR", f"Out of date: {why}; bake again or go back to live"))
    return lines


def look_note(obj):
    """What the Look settings leave alone, or None: the ocean wears the user's own material
    (never written; Clarity and Water Colour still set our water body under it)."""
    data = obj.data
    mat = data.materials[0] if data is not None and len(data.materials) else None
    if mat is not None and not scene.owns(mat):
        return (f"Material {mat.name!r} is your own: the colours leave it as it is (Clarity "
                "and Water Colour still tint the water body below)")
    return None


def effect_lines(obj):
    """(effect, "on: reason" or "off: reason") for the last built frame."""
    decisions = frame.last_effects(obj)
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
        else:
            layout.label(text=obj.name, icon="OBJECT_DATA")


class _OceanSubPanel:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Ocean"
    bl_parent_id = "VIEW3D_PT_projgrid_ocean"

    @classmethod
    def poll(cls, context):
        return active_ocean(context) is not None

    def settings(self, context):
        self.layout.use_property_split = True
        self.layout.use_property_decorate = True  # keyframe dots: every setting animates
        return active_ocean(context).projgrid


class VIEW3D_MT_projgrid_sea_state(bpy.types.Menu):
    """Every force of the Beaufort scale, by name"""

    bl_label = "Sea State"

    def draw(self, context):
        for force, (name, *_) in sea_states.BEAUFORT.items():
            self.layout.operator("projgrid.sea_state", text=f"{force}  {name}").beaufort = force


class VIEW3D_PT_projgrid_waves(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Waves"

    def draw(self, context):
        s = self.settings(context)
        layout = self.layout
        row = layout.row(align=True)
        row.menu(VIEW3D_MT_projgrid_sea_state.__name__, text="Sea State")
        for force in (2, 4, 6, 8, 10):
            row.operator("projgrid.sea_state", text=str(force)).beaufort = force
        col = layout.column()
        col.prop(s, "height_source")
        col.prop(s, "wind_speed")
        col.prop(s, "wind_direction")
        col.prop(s, "gusts")
        col.prop(s, "choppiness")
        if s.height_source == "SPECTRUM":
            col.prop(s, "spectrum")
            col.prop(s, "fetch")
            col = layout.column(heading="Swell")
            col.prop(s, "swell_height", text="Height")
            col.prop(s, "swell_direction", text="Direction")
            col.prop(s, "swell_period", text="Period")
            layout.prop(s, "seed")
        else:
            col.prop(s, "noise_from_wind")
            sub = col.column()
            sub.active = s.noise_from_wind
            sub.prop(s, "spectrum")
            sub.prop(s, "fetch")
            sub = col.column()
            sub.active = not s.noise_from_wind
            sub.prop(s, "amplitude")
            sub.prop(s, "wave_scale")
            for prop in ("octaves", "roughness", "speed", "seed", "noise"):
                col.prop(s, prop)


class VIEW3D_PT_projgrid_grid(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Grid"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        s = self.settings(context)
        col = self.layout.column(align=True)
        col.prop(s, "resolution_x", text="Viewport X")
        col.prop(s, "resolution_y", text="Y")
        col = self.layout.column(align=True)
        col.prop(s, "render_resolution_x", text="Render X")
        col.prop(s, "render_resolution_y", text="Y")
        self.layout.prop(s, "projector_elevation")


class VIEW3D_PT_projgrid_look(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Look"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        s = self.settings(context)
        col = self.layout.column()
        col.prop(s, "water_colour")
        col.prop(s, "clarity")
        col.prop(s, "foam_colour")
        note = look_note(active_ocean(context))
        if note:
            self.layout.label(text=note, icon="INFO")


class VIEW3D_PT_projgrid_effects(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Effects"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        s = self.settings(context)
        for effect, text in effect_lines(active_ocean(context)):
            col = self.layout.column(align=True)
            col.prop(s, effect)
            col.label(text=text)


class VIEW3D_PT_projgrid_bake(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Bake"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        obj = active_ocean(context)
        layout = self.layout
        lines = bake_lines(obj, context.scene)
        for icon, text in lines:
            layout.label(text=text, icon=icon)
        row = layout.row(align=True)
        out_of_date = any(icon == "ERROR" for icon, _ in lines)
        op = row.operator("projgrid.bake", icon="RENDER_ANIMATION", text=(
            "Re-bake" if out_of_date else "Bake Again" if lines else "Bake"))
        mod = baked.cache_modifier(obj)
        if mod is not None and mod.cache_file is not None:  # the same file and frames
            op.filepath = mod.cache_file.filepath
            op.frame_start, op.frame_end = obj.projgrid.bake_frames
        if lines:
            row.operator("projgrid.bake_free", icon="LOOP_BACK")
        else:
            layout.label(text="For farms that run no scripts, and other packages", icon="INFO")


class VIEW3D_PT_projgrid_status(_OceanSubPanel, bpy.types.Panel):
    bl_label = "Status"

    def draw(self, context):
        for icon, text in stats_lines(active_ocean(context), context.scene):
            self.layout.label(text=text, icon=icon)
