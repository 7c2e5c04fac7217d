"""Where Blender meets the core: the ocean's settings, its camera, its mesh and material inputs.

The only module of the core that imports bpy. Everything here reads Blender data, calls the core,
and writes our own ocean mesh and material; it never writes anything of the user's.
"""

import time
from dataclasses import dataclass

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

from ..shaders import water
from ..shaders.nodes import TAG, assign
from . import Camera, HeightField, build_grid, corner_uv, effects, grid_topology, memory
from .camera import blender_projection, rigid_view
from .projected_grid import check_resolution

UV_MAP = "ProjectorUV"
OVERRIDABLE = {"LIBRARY_OVERRIDABLE"}  # a library override of an ocean keeps its own settings
# ID property of a stand-in: the appearance it draws (see `Appearance.key`).
STAND_IN = "projgrid_stand_in"

# Per-surface runtime state, keyed by the surface object's name_full (the ocean, or the stand-in
# drawing it): stats for the panel, the message of the last refused rebuild, a warning about the
# last built one, and the signature of the last build (to skip identical rebuilds).
STATE = {}
# Set by the render handlers; the live preview steps aside while it is true.
RENDERING = {"active": False}
# The 3D view the live preview follows: {"view": 4x4, "proj": 4x4} or empty.
LIVE_VIEW = {}
# Appearance key -> name_full of the stand-in drawing it (a cache, checked on every use).
STAND_INS = {}


def _settings_changed(self, context):
    """Rebuild at once with the values just set (the evaluated copy is updated only later)."""
    obj = self.id_data
    if context.scene is not None and obj.projgrid.is_ocean and not RENDERING["active"]:
        update_ocean(obj, context.scene, context.evaluated_depsgraph_get(), settings=self)


def _mode(effect, description):
    return EnumProperty(
        name=effect.replace("_", " ").title(), default="AUTO", update=_settings_changed,
        description=description,
        override=OVERRIDABLE,
        items=(("AUTO", "Auto", "On when the scene calls for it, decided each frame"),
               ("ON", "On", "Always on"), ("OFF", "Off", "Always off: costs nothing")))


def _active_effects(self):
    """Bit set of the effects on for the last built frame (read-only `active_effects`)."""
    decisions = STATE.get(self.id_data.name_full, {}).get("effects") or {}
    return sum(1 << i for i, e in enumerate(effects.EFFECTS) if decisions.get(e, (False,))[0])


def _int(name, description, default, lo, hi, soft_hi=None):
    return IntProperty(name=name, description=description, default=default, min=lo, max=hi,
                       soft_max=soft_hi or hi, update=_settings_changed, override=OVERRIDABLE)


def _float(name, description, default, lo, hi, soft_hi, unit="NONE", **kw):
    return FloatProperty(name=name, description=description, default=default, min=lo, max=hi,
                         soft_max=soft_hi, unit=unit, update=_settings_changed,
                         override=OVERRIDABLE, **kw)


class ProjectedGridSettings(bpy.types.PropertyGroup):
    """`obj.projgrid`: the ocean's settings (all animatable) and the effects on this frame."""

    is_ocean: BoolProperty(name="Is Ocean", default=False, options={"HIDDEN"})
    resolution_x: _int("Resolution X", "Grid vertices across the screen in the viewport",
                       65, 2, 8193, 1025)
    resolution_y: _int("Resolution Y", "Grid vertices up the screen in the viewport",
                       129, 2, 8193, 2049)
    render_resolution_x: _int("Render X", "Grid vertices across the screen in renders",
                              257, 2, 8193, 2049)
    render_resolution_y: _int("Render Y", "Grid vertices up the screen in renders",
                              513, 2, 8193, 4097)
    amplitude: _float("Amplitude", "Height of the largest waves (the bound is the sum over "
                      "octaves)", 0.5, 0.0, 1e4, 10.0, "LENGTH")
    wave_scale: _float("Wave Scale", "Wavelength of the first octave", 40.0, 0.01, 1e5, 500.0,
                       "LENGTH")
    octaves: _int("Octaves", "Noise octaves, each half the wavelength of the one before",
                  8, 0, 24)
    roughness: _float("Roughness", "Amplitude ratio between octaves (alpha)", 0.5, 0.0, 2.0,
                      1.0)
    speed: _float("Speed", "Time scale of the animation", 1.0, -100.0, 100.0, 10.0)
    seed: _int("Seed", "Noise seed", 0, 0, 2**31 - 1, 1000)
    projector_elevation: _float("Projector Elevation", "Extra height of the projector above "
                                "the waves (thesis §2.5)", 0.0, 0.0, 1e4, 100.0, "LENGTH")
    noise: EnumProperty(
        name="Noise", default="FAST", update=_settings_changed, override=OVERRIDABLE,
        description="How heights are evaluated (docs/benchmarks.md has the cost and the error)",
        items=(("FAST", "Fast", "Per-octave noise textures sampled bilinearly (thesis App. B)"),
               ("EXACT", "Exact", "Gradient noise evaluated at every vertex (the reference)")))
    wind_speed: _float("Wind Speed", "Wind at 10 m above the sea; sets the whitecap coverage of "
                       "the foam (Monahan and Mac Niocaill)", 3.0, 0.0, 100.0, 30.0, "VELOCITY")
    foam: _mode("foam", "Foam on wave crests, its coverage set by the wind")
    contact_foam: _mode("contact_foam", "Foam where objects cross the water surface")
    underwater: _mode("underwater", "Snell's window and absorption fog with the camera below "
                      "the surface")
    refraction: _mode("refraction", "Submerged objects seen through the surface, dimmed and "
                      "tinted with depth")
    caustics: _mode("caustics", "Sunlight focused by the waves onto submerged geometry")
    godrays: _mode("godrays", "Shafts of sunlight seen from under the water")
    local_reflections: _mode("local_reflections", "Reflections of objects above the water "
                             "(sky only without them)")
    sun_glint: _mode("sun_glint", "The sun's highlight on the waves")
    water_body: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                description="Our water body volume (underwater, refraction)")
    shadow_caster: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                   description="Our object casting the water's caustic shadow")
    reflection_probe: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                      description="Our sphere probe capturing the mirror image "
                                      "(local reflections)")
    source: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                            description="On a stand-in of ours: the ocean whose sea it draws "
                            "(a linked, overridden or instanced ocean we may not write)")
    active_effects: EnumProperty(
        name="Active Effects", options={"ENUM_FLAG"}, get=_active_effects,
        description="The effects on for the current frame (read-only)",
        items=[(e.upper(), e.replace("_", " ").title(), "", 1 << i)
               for i, e in enumerate(effects.EFFECTS)])


def height_field(settings):
    """The core HeightField for (possibly evaluated) settings."""
    return HeightField(amplitude=settings.amplitude, wave_scale=settings.wave_scale,
                       octaves=settings.octaves, roughness=settings.roughness,
                       speed=settings.speed, seed=settings.seed,
                       method=settings.noise.lower())


def ocean_objects(scene):
    """The oceans placed in `scene` itself."""
    return [obj for obj in scene.objects if obj.type == "MESH" and obj.projgrid.is_ocean]


def all_oceans():
    """Every ocean of the file, linked ones included."""
    return [obj for obj in bpy.data.objects if obj.type == "MESH" and obj.projgrid.is_ocean]


def owns(id_block):
    return id_block is not None and bool(id_block.get(TAG))


def local(id_block):
    """Data of this file: neither linked from a library nor a library override."""
    return id_block.library is None and id_block.override_library is None


def writable(obj):
    """Whether the ocean's own mesh is ours to write: a local object with a local mesh (a linked
    ocean's or a library override's mesh belongs to its library, which we never write)."""
    return local(obj) and obj.data is not None and local(obj.data)


@dataclass
class Appearance:
    """One place an ocean shows in a scene: in the scene or a background set of it (`chain`
    empty), or inside collection instances (`chain`: (instancer, instanced collection) pairs,
    outermost first)."""

    ocean: object
    chain: tuple = ()
    count: int = 1  # the ocean's appearances in the scene

    @property
    def key(self):
        """What a stand-in of ours draws: the ocean's and the instancers' full names."""
        return "|".join(o.name_full for o in (self.ocean, *(i for i, _ in self.chain)))

    @property
    def needs_stand_in(self):
        """Drawn by a stand-in of ours: the ocean's mesh is not ours to write, or it shows more
        than once (one mesh cannot be right in two places)."""
        return self.count > 1 or not writable(self.ocean)

    @property
    def objects(self):
        """The ocean and its instancers: the objects whose visibility decides whether it shows."""
        return (self.ocean, *(i for i, _ in self.chain))

    def world(self, depsgraph):
        """The ocean's evaluated world matrix where it shows (float64)."""
        m = np.eye(4)
        for instancer, collection in self.chain:
            offset = np.eye(4)
            offset[:3, 3] = -np.array(collection.instance_offset, dtype=np.float64)
            m = m @ np.array(instancer.evaluated_get(depsgraph).matrix_world,
                             dtype=np.float64) @ offset
        return m @ np.array(self.ocean.evaluated_get(depsgraph).matrix_world, dtype=np.float64)

    def shown(self, depsgraph, render):
        """Whether this evaluation draws it: each object on the way is in the depsgraph (so
        visible in renders or viewports and not in an excluded collection), and in the viewport
        the outermost one is not hidden in the view layer."""
        if not all(o.evaluated_get(depsgraph).is_evaluated for o in self.objects):
            return False
        if render:
            return True
        try:
            return not self.objects[-1 if not self.chain else 1].hide_get()
        except RuntimeError:  # not in this view layer (a background set's object)
            return True


def _placements(obj, scenes, parents, depth=0):
    """The instancer chains through which `obj` shows in `scenes` (the empty chain: directly)."""
    chains = []
    users = obj.users_scene
    if any(s in users for s in scenes):
        chains.append(())
    if depth >= 8:  # instances nested deeper than this are left out
        return chains
    holders, todo = [], list(obj.users_collection)
    while todo:
        c = todo.pop()
        if c not in holders:
            holders.append(c)
            todo.extend(parents.get(c.as_pointer(), ()))
    for collection in holders:
        for instancer in collection.users_dupli_group:
            for outer in _placements(instancer, scenes, parents, depth + 1):
                chains.append(outer + ((instancer, collection),))
    return chains


def appearances(scene, only=None):
    """Every place an ocean (or only `only`) shows in `scene`, its background sets included."""
    oceans = all_oceans() if only is None else [only]
    if not oceans:
        return []
    scenes = [scene]
    while scenes[-1].background_set is not None and len(scenes) < 16:
        if scenes[-1].background_set in scenes:
            break
        scenes.append(scenes[-1].background_set)
    parents = {}
    for collection in bpy.data.collections:
        for child in collection.children:
            parents.setdefault(child.as_pointer(), []).append(collection)
    found = []
    for ocean in oceans:
        chains = _placements(ocean, scenes, parents)
        found += [Appearance(ocean, chain, len(chains)) for chain in chains]
    return found


def _stand_in_collection(app, scene):
    """Where a new stand-in goes: the first local collection holding the outermost object, so
    the stand-in shares its view-layer exclusion, holdout and indirect-only flags."""
    top = app.objects[1] if app.chain else app.ocean
    return next((c for c in top.users_collection if local(c)), scene.collection)


def stand_in(app, scene, create):
    """Our local object drawing `app` (made if missing and `create`), or None."""
    key = app.key
    obj = bpy.data.objects.get(STAND_INS.get(key, ""))
    if obj is None or obj.get(STAND_IN) != key:
        obj = next((o for o in bpy.data.objects if o.get(STAND_IN) == key and owns(o)), None)
    if obj is None and create:
        name = f"{app.ocean.name} Sea"
        mesh = bpy.data.meshes.new(name)
        mesh[TAG] = True
        mesh.materials.append(water.material())
        obj = bpy.data.objects.new(name, mesh)
        obj[TAG] = True
        obj[STAND_IN] = key
        obj.projgrid.source = app.ocean
        obj.hide_select = True
        if hasattr(obj, "cycles"):
            obj.cycles.use_deform_motion = False
        _stand_in_collection(app, scene).objects.link(obj)
        ensure_companions(obj)
    if obj is not None:
        STAND_INS[key] = obj.name_full
    return obj


def surface_for(app, scene, create):
    """The local object of ours whose mesh draws `app`: the ocean itself when we may write it
    and it shows once, else a stand-in of ours (None if it is missing and may not be made)."""
    if not app.needs_stand_in:
        return app.ocean
    return stand_in(app, scene, create)


def remove_stale_stand_ins(scene, apps, everywhere=False):
    """Delete the stand-ins whose appearance in `scene` is gone or no longer needs one (`apps`:
    the scene's appearances), with their companions: those this session made, or `everywhere`
    in the scene (after a load or a deletion)."""
    needed = {a.key for a in apps if a.needs_stand_in}
    if everywhere:
        candidates = [o for o in scene.objects if o.get(STAND_IN)]
    else:
        candidates = [o for o in map(bpy.data.objects.get, list(STAND_INS.values()))
                      if o is not None]
    stale = [o for o in candidates if owns(o) and o.get(STAND_IN) and scene in o.users_scene
             and (o.projgrid.source is None or o[STAND_IN] not in needed)]
    for obj in stale:
        STATE.pop(obj.name_full, None)
        STAND_INS.pop(obj[STAND_IN], None)
        for prop in COMPANIONS:
            companion = getattr(obj.projgrid, prop)
            if companion is not None and owns(companion) and companion != obj:
                _remove_object(companion)
        _remove_object(obj)
    return len(stale)


def render_size(scene):
    r = scene.render
    pct = r.resolution_percentage / 100.0
    return (max(1, round(r.resolution_x * pct)), max(1, round(r.resolution_y * pct)),
            r.pixel_aspect_x, r.pixel_aspect_y)


def scene_camera(scene):
    """The camera this frame renders with: the timeline markers' camera switch, which Blender
    applies to `scene.camera` only after frame_change_post (BKE_scene_camera_switch_find)."""
    markers = [(m.frame, m.camera) for m in scene.timeline_markers
               if m.camera is not None and not m.camera.hide_render]
    if not markers:
        return scene.camera
    past = [m for m in markers if m[0] <= scene.frame_current]
    if past:
        return max(past, key=lambda m: m[0])[1]
    return min(markers, key=lambda m: m[0])[1]


def camera_for(scene, depsgraph, camera=None):
    """(view, proj) float64 of the camera rendering this frame (ValueError with a user message
    if none or not usable), built from the camera's own settings: Blender's float32 matrix
    loses the far corners for clip ranges wider than about 1e7 (camera.blender_projection)."""
    cam = camera or scene_camera(scene)
    if cam is None:
        raise ValueError("the scene has no camera (set one, or use Live Preview)")
    cam_eval = cam.evaluated_get(depsgraph)
    x, y, sx, sy = render_size(scene)
    view = rigid_view(cam_eval.matrix_world)
    if cam_eval.type != "CAMERA":  # a lamp or empty as the camera: Blender's defaults
        proj = cam_eval.calc_matrix_camera(depsgraph, x=x, y=y, scale_x=sx, scale_y=sy)
        return view, np.array(proj, dtype=np.float64)
    data = cam_eval.data
    if data.type == "PANO":
        raise ValueError(f"camera {cam.name!r} is panoramic; the projected grid needs a "
                         "perspective or orthographic camera")
    try:
        proj = blender_projection(data.type == "ORTHO", data.lens, data.ortho_scale,
                                  (data.sensor_width, data.sensor_height), data.sensor_fit,
                                  (data.shift_x, data.shift_y),
                                  (data.clip_start, data.clip_end), (x, y), (sx, sy))
    except ValueError as e:
        raise ValueError(f"camera {cam.name!r}: {e}") from None
    return view, proj


def scene_time(scene):
    """Seconds at the current (sub)frame."""
    r = scene.render
    return (scene.frame_current + scene.frame_subframe) * r.fps_base / r.fps


def update_ocean(obj, scene, depsgraph, render=None, view=None, settings=None):
    """Rebuild the sea of ocean `obj` wherever it shows in `scene` (see `update_appearance`);
    returns the first refusal message or None."""
    messages = [update_appearance(app, scene, depsgraph, render, view, settings)
                for app in appearances(scene, only=obj)]
    return next((m for m in messages if m), None)


def ocean_axes(world):
    """The inverse of an ocean's linear transform (ValueError saying what to change if none)."""
    linear = world[:3, :3]
    if not np.all(np.isfinite(world)):
        raise ValueError("the ocean object's transform is not finite: reset its location, "
                         "rotation and scale")
    lengths = np.sqrt((linear * linear).sum(axis=0))
    zero = [axis for axis, length in zip("XYZ", lengths, strict=True) if length == 0.0]
    # Independent axes: the volume they span is not negligible against their lengths.
    if zero or abs(np.linalg.det(linear)) <= 1e-12 * lengths.prod():
        axes = "/".join(zero) or "one axis"
        raise ValueError(f"the ocean object's scale is zero on {axes}: give it a non-zero scale "
                         "(the sea ignores its scale and rotation, but needs them invertible)")
    return np.linalg.inv(linear)


def flat_warning(hf, result, settings):
    """Why a built sea has no wave in its geometry, and what to change (None if it has)."""
    if not result.visible or hf.amplitude == 0.0 or hf.octaves == 0 or result.lod.max() > 0.0:
        return None
    spacing = hf.wave_scale / 2.0 ** (float(result.lod.max()) + 1.0)
    text = (f"no wave is in the geometry: the grid's vertices lie {spacing:.3g} m apart or "
            f"more, beyond the longest wave ({hf.wave_scale:.3g} m); ")
    if settings.projector_elevation > hf.bound:
        return text + (f"Projector Elevation ({settings.projector_elevation:.3g} m) lifts the "
                       "projector far above the waves: lower it")
    return text + (f"Amplitude ({hf.amplitude:.3g} m) makes the waves {hf.bound:.3g} m high, "
                   "so the projector sits that high: lower Amplitude or raise Wave Scale")


def update_appearance(app, scene, depsgraph, render=None, view=None, settings=None):
    """Rebuild the grid drawing `app` for the current frame; returns the refusal message or None.

    `render` defaults to whether `depsgraph` is a render depsgraph: renders use the render camera
    and resolution, the viewport the live preview's view if one runs, else the scene camera.
    Settings are read from the evaluated ocean, so animated values are honoured in renders,
    unless `settings` are given (a settings edit passes the values just set). The mesh written
    is ours: the ocean's own, or a stand-in's for an ocean we may not write or that shows more
    than once (`surface_for`).
    """
    if render is None:
        render = depsgraph.mode == "RENDER"
    ocean = app.ocean
    surface = surface_for(app, scene, create=not render and not RENDERING["active"])
    STATE.setdefault(ocean.name_full, {})["drawn_by"] = (
        None if surface is ocean else STAND_INS.get(app.key))
    if surface is not ocean and writable(ocean) and owns(ocean.data):
        _empty(ocean.data)  # its own mesh shows in every instance: the stand-ins draw it
    if surface is None:
        return _refuse(STATE.setdefault(ocean.name_full, {}), None,
                       "its stand-in is made at the next viewport update or render start")
    state = STATE.setdefault(surface.name_full, {})
    if not owns(surface.data):
        return _refuse(state, None, "the ocean's mesh was replaced; it is left untouched "
                       "(Add Ocean makes a new one)")
    if surface.data.is_editmode:
        return _refuse(state, None, f"{surface.name!r} is in Edit Mode: the grid is rebuilt "
                       "when you leave it")
    mesh = surface.data
    shown = app.shown(depsgraph, render)
    hidden = follow_visibility(surface, app, shown, render)
    if not shown:
        state.update(key=None, message=None, warning=None, hidden=True)
        return None
    settings = settings or ocean.evaluated_get(depsgraph).projgrid
    try:
        if render:
            res = (settings.render_resolution_x, settings.render_resolution_y)
        else:
            res = (settings.resolution_x, settings.resolution_y)
        res = check_resolution(res)
        if view is None and not render and LIVE_VIEW:
            view = (LIVE_VIEW["view"], LIVE_VIEW["proj"])
        camera = view if view is not None else camera_for(scene, depsgraph)
        world = app.world(depsgraph)
        to_local = ocean_axes(world)
        if surface is not ocean:  # the stand-in sits where the ocean shows, unrotated
            assign(surface, location=tuple(world[:3, 3]), rotation_euler=(0.0, 0.0, 0.0),
                   scale=(1.0, 1.0, 1.0))
            to_local = np.eye(3)
        t = scene_time(scene)
        hf = height_field(settings)
        cam = Camera(*camera)
        sun = water.sun_lamp(scene, depsgraph)  # once per frame: the facts and the glint
        facts = scene_facts(surface, scene, sun, cam, world[2, 3], hf, settings, render)
        key = (render, res, np.asarray(camera[0]).tobytes(), np.asarray(camera[1]).tobytes(),
               world.tobytes(), t, tuple(getattr(settings, p) for p in SETTINGS),
               mesh.session_uid, facts.key())
        if key == state.get("key"):
            return None
        memory.check_grid(res, len(mesh.vertices) != res[0] * res[1],
                          "render" if render else "viewport", large_only=True)
        start = time.perf_counter()
        result = build_grid(cam, hf, level=world[2, 3], time=t, resolution=res,
                            projector_elevation=settings.projector_elevation,
                            origin=world[:3, 3])
        decisions = effects.decide({e: getattr(settings, e) for e in effects.EFFECTS}, facts)
        on = {e: d[0] for e, d in decisions.items()}
    except ValueError as e:
        return _refuse(state, mesh, str(e))
    except MemoryError:
        return _refuse(state, mesh, f"out of memory building the {res[0]}x{res[1]} grid: lower "
                       "the grid resolution")
    try:
        write_mesh(mesh, result, to_local)
        write_foam(mesh, result, hf, settings, t, on, facts, world[2, 3])
        write_caustics(mesh, result, facts, on)
        write_godrays(surface, hf, t, cam, world[2, 3], facts, on)
    except (MemoryError, RuntimeError) as e:
        kind = "out of memory" if isinstance(e, MemoryError) else str(e)
        return _refuse(state, mesh, f"writing the {res[0]}x{res[1]} grid failed ({kind}): lower "
                       "the grid resolution")
    state.update(key=key, message=None, vertices=len(result.positions),
                 grid=result.without_surface(),
                 ms=(time.perf_counter() - start) * 1e3, effects=decisions,
                 shader_octaves=result.shader_octaves, resolution=res, render=render,
                 warning=flat_warning(hf, result, settings), hidden=False)
    in_use = effects_in_use()
    water.update_inputs(surface, sun, hf, result.shader_octaves, t, in_use)
    if not render and not RENDERING["active"]:
        ensure_companions(surface)
        own_material(surface)
    place_companions(surface, cam, world[2, 3], hf.bound, on, scene, in_use, hidden)
    return None


def follow_visibility(surface, app, shown, render):
    """A stand-in and the companions follow their ocean where it shows: hidden with it (in
    renders by the render's own evaluation, in the viewport by the objects' flags), and a
    holdout with it; returns (hidden in renders, hidden in the viewport). The ocean's own flags
    are the user's and are never written. Companions share the surface's collections, so they
    also share its view-layer exclusion and its collections' holdout and indirect-only."""
    hidden_render = any(o.hide_render for o in app.objects)
    hidden_viewport = any(o.hide_viewport for o in app.objects)
    if render:
        hidden_render = hidden_render or not shown
    holdout = any(o.is_holdout for o in app.objects)
    ours = [surface] if surface is not app.ocean else []
    ours += [c for c in (getattr(surface.projgrid, p) for p in COMPANIONS)
             if c is not None and owns(c) and c != surface]
    hidden_viewport = hidden_viewport or (not render and not shown)
    for obj in ours:
        assign(obj, is_holdout=holdout)
        if obj is surface:
            assign(obj, hide_render=hidden_render, hide_viewport=hidden_viewport)
        elif not shown or hidden_render or hidden_viewport:
            assign(obj, hide_render=hidden_render or not shown,
                   hide_viewport=hidden_viewport or not shown)
        if obj is not surface and set(obj.users_collection) != set(surface.users_collection):
            _link_like(obj, surface)
    return hidden_render, hidden_viewport


def _link_like(obj, model):
    """Put our `obj` in exactly the collections `model` is in."""
    for collection in model.users_collection:
        if collection not in obj.users_collection and local(collection):
            collection.objects.link(obj)
    for collection in obj.users_collection:
        if collection not in model.users_collection:
            collection.objects.unlink(obj)


SETTINGS = ("resolution_x", "resolution_y", "render_resolution_x", "render_resolution_y",
            "amplitude", "wave_scale", "octaves", "roughness", "speed", "seed",
            "projector_elevation", "noise", "wind_speed", *effects.EFFECTS)
# Object types with geometry that can stand in, on or under the water.
GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME",
                  "GPENCIL", "GREASEPENCIL"}


def scene_objects(scene, ocean, camera, render, level):
    """SceneObjects (effects.py) for the visible geometry of the scene other than oceans and
    our own objects, heights relative to the water `level`."""
    found, boxes = [], []
    local = np.empty((8, 3), dtype=np.float32)
    for obj in scene.objects:
        if (obj.type not in GEOMETRY_TYPES or obj == ocean or obj.projgrid.is_ocean
                or owns(obj)):
            continue
        hidden = obj.hide_render if render else obj.hide_viewport
        if hidden:
            continue
        obj.bound_box.foreach_get(local.reshape(-1))  # evaluated geometry; 12x np.array's speed
        world = np.array(obj.matrix_world, dtype=np.float64)
        boxes.append(local @ world[:3, :3].T + world[:3, 3])
        found.append(obj.name)
    if not boxes:
        return []
    boxes = np.stack(boxes)
    mirrored = boxes * (1.0, 1.0, -1.0) + (0.0, 0.0, 2.0 * level)
    seen = effects.boxes_in_view(camera, np.concatenate([boxes, mirrored])).reshape(2, -1)
    z = boxes[..., 2] - level
    return [effects.SceneObject(name, float(lo), float(hi), bool(v), box, bool(m))
            for name, lo, hi, v, m, box in zip(found, z.min(axis=1), z.max(axis=1), *seen, boxes,
                                               strict=True)]


def scene_facts(obj, scene, sun, camera, level, hf, settings, render):
    """effects.SceneFacts of this frame: camera against the water, objects, sun, wind.
    Object heights are relative to the water level, as the camera's; `sun` is the evaluated
    sun lamp (water.sun_lamp) or None."""
    elevation = direction = None
    if sun is not None:
        direction = tuple(water.sun_direction(sun))
        elevation = float(np.degrees(np.arcsin(np.clip(direction[2], -1.0, 1.0))))
    needs_objects = any(getattr(settings, e) == "AUTO" for e in
                        ("contact_foam", "refraction", "caustics", "local_reflections"))
    needs_objects = needs_objects or any(getattr(settings, e) == "ON" for e in
                                         ("contact_foam", "caustics"))
    objects = scene_objects(scene, obj, camera, render, level) if needs_objects else []
    return effects.SceneFacts(camera_height=float(camera.position[2] - level), bound=hf.bound,
                              wind_speed=settings.wind_speed, sun_elevation=elevation,
                              objects=objects, sun_direction=direction)


def write_attribute(mesh, name, values):
    """Our per-vertex float attribute `name` set to `values`, or removed when None (so a branch
    another ocean keeps unmuted cannot show stale values)."""
    if values is None:
        if name in mesh.attributes:
            mesh.attributes.remove(mesh.attributes[name])
        return
    if name not in mesh.attributes:
        mesh.attributes.new(name, "FLOAT", "POINT")
    mesh.attributes[name].data.foreach_set("value", values)


def contact_foam_width(hf):
    """How far contact foam reaches from an object: half a metre plus the waves' bound."""
    return 0.5 + hf.bound


def write_foam(mesh, result, hf, settings, t, on, facts, level):
    """The per-vertex foam of this frame: crests (foam) and rings around the objects crossing
    the surface (contact foam), each computed only while on."""
    foam = None
    if result.visible and on["foam"]:
        coverage = max(effects.whitecap_coverage(settings.wind_speed), effects.FOAM_MIN_COVERAGE)
        threshold = effects.foam_threshold(hf, t, coverage)
        foam = effects.foam_amount(result.surface[2].ravel(), threshold, 0.25 * hf.amplitude)
    boxes = effects.crossing_boxes(facts) if result.visible and on["contact_foam"] else ()
    if len(boxes):
        x, y, h = result.surface
        ring = effects.contact_foam(x, y, h + level, boxes, contact_foam_width(hf))
        foam = ring if foam is None else np.maximum(foam, ring)
    write_attribute(mesh, water.FOAM_ATTRIBUTE, foam)


def write_caustics(mesh, result, facts, on):
    """The caustic shadow (Fleck Eq. 28), while caustics are on."""
    values = None
    if result.visible and on["caustics"] and facts.sun_direction is not None:
        intensity = effects.caustic_intensity(result.surface, facts.sun_direction,
                                              effects.receiving_depth(facts))
        values = effects.caustic_shadow(intensity) - np.float32(effects.CAUSTIC_MEAN)
    write_attribute(mesh, water.CAUSTIC_ATTRIBUTE, values)


GODRAY_TILE_SIZE = 32.0  # metres across the godrays' caustic tile (repeated beyond)


def write_godrays(obj, hf, t, cam, level, facts, on):
    """While godrays are on: the caustic tile around the camera into the water body's material.
    Texel-aligned, so the pattern stays put in the world as the camera moves."""
    body = obj.projgrid.water_body
    if not on["godrays"] or facts.sun_direction is None or body is None or not owns(body):
        return
    mat = body.data.materials[0] if len(body.data.materials) else None
    if mat is None or not owns(mat):
        return
    size = GODRAY_TILE_SIZE
    texel = size / water.CAUSTIC_TILE
    centre = np.round(np.asarray(cam.position[:2]) / texel) * texel
    depth = max(-facts.camera_height, 1.0)  # the light around the eye
    tile = effects.caustic_tile(hf, t, centre, size, water.CAUSTIC_TILE, facts.sun_direction,
                                depth)
    np.clip(tile, 0.0, 4.0, out=tile)  # a focus's singular peak would be a firefly
    water.update_godrays(mat, tile, effects.tile_lookup(facts.sun_direction, level,
                                                        centre - 0.5 * size, size))


COMPANIONS = {  # setting: (name suffix, effects that show it)
    "water_body": (" Water Body", ("underwater", "refraction")),
    # Light passes the water: the ocean casts no shadow of its own while this one is shown.
    "shadow_caster": (" Shadow", ("underwater", "refraction", "caustics", "godrays")),
    # The ocean is left out of sphere probes' captures while this one is shown.
    "reflection_probe": (" Reflection", ("local_reflections",)),
}


def _new_companion(obj, prop, name):
    """The data of a new companion: a closed unit box, the ocean's own mesh (the caster draws
    it again with our shadow material, linked to the object), or a sphere light probe with a
    box influence and a parallax volume set per frame (effects.mirror_capture)."""
    if prop == "shadow_caster":
        return obj.data
    if prop == "water_body":
        data = bpy.data.meshes.new(name)
        data.from_pydata([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], [],
                         [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
                          (1, 5, 7, 3)])
        data.materials.append(water.body_material())
    else:
        data = bpy.data.lightprobes.new(name, "SPHERE")
        data.influence_type, data.influence_distance, data.falloff = "BOX", 1.0, 0.0
        data.use_custom_parallax, data.parallax_type = True, "BOX"
    data[TAG] = True
    return data


COMPANION = "projgrid_companion"  # ID property naming a companion's setting on its ocean


def own_material(surface):
    """The surface's water material is its own (water.own_material)."""
    water.own_material(surface.data)


def _remove_object(obj):
    """Delete our object, and its data when it is ours and nothing else uses it."""
    data, obj_type = obj.data, obj.type
    bpy.data.objects.remove(obj)
    if data is not None and owns(data) and data.users == 0:
        kind = bpy.data.lightprobes if obj_type == "LIGHT_PROBE" else bpy.data.meshes
        kind.remove(data)


def remove_orphan_companions():
    """Delete our stand-ins whose ocean was deleted, then our companions no ocean or stand-in
    points to any more, with their data when nothing else uses it; returns how many."""
    gone = [o for o in bpy.data.objects
            if o.get(STAND_IN) and owns(o) and o.projgrid.source is None]
    for obj in gone:
        _remove_object(obj)
    kept = {getattr(o.projgrid, prop) for o in bpy.data.objects
            if o.projgrid.is_ocean or o.get(STAND_IN) for prop in COMPANIONS}
    orphans = [o for o in bpy.data.objects if o.get(COMPANION) and owns(o) and o not in kept]
    for obj in orphans:
        _remove_object(obj)
    return len(gone) + len(orphans)


def ensure_companions(obj):
    """Our water body, shadow caster and reflection probe for an ocean, made hidden if missing
    (never in a render: the render's depsgraph is built from what exists at render_init)."""
    settings = obj.projgrid
    collection = obj.users_collection[0] if obj.users_collection else None
    if collection is None:
        return
    # A duplicated ocean (Shift+D) has its original's settings, pointers included: the caster,
    # parented to the original, tells, and the copy makes companions of its own.
    caster = settings.shadow_caster
    copied = caster is not None and caster.parent not in (None, obj)
    for prop, (suffix, _) in COMPANIONS.items():
        current = getattr(settings, prop)
        if (not copied and current is not None and owns(current)
                and current.name in bpy.data.objects):
            if current.get(COMPANION) != prop:  # made before the key existed
                current[COMPANION] = prop
            continue
        companion = bpy.data.objects.new(obj.name + suffix, _new_companion(obj, prop,
                                                                           obj.name + suffix))
        companion[TAG] = True
        companion[COMPANION] = prop
        companion.hide_render = companion.hide_viewport = True
        companion.hide_select = True
        companion.hide_probe_sphere = True  # never in our reflection's capture
        if prop == "water_body":
            companion.visible_shadow = False
        if prop == "shadow_caster":
            companion.parent = obj
            for slot in companion.material_slots:
                slot.link = "OBJECT"
                slot.material = water.shadow_material()
            for ray in ("camera", "diffuse", "glossy", "transmission", "volume_scatter"):
                setattr(companion, f"visible_{ray}", False)
        collection.objects.link(companion)
        setattr(settings, prop, companion)


def place_companions(obj, cam, level, bound, on, scene, in_use, hidden=(False, False)):
    """Show each companion only while an effect needs it (hidden, it costs nothing) and its
    ocean is not `hidden` (in renders, in the viewport): the water body centred under the
    camera at the water level and as wide as EEVEE draws volumes, the reflection probe at the
    camera mirrored in the water, reaching as far as the camera sees."""
    for prop, (_, needed_by) in COMPANIONS.items():
        companion = getattr(obj.projgrid, prop)
        if companion is None or not owns(companion):
            continue
        hide = not any(on[e] for e in needed_by)
        assign(companion, hide_render=hide or hidden[0], hide_viewport=hide or hidden[1])
        if prop == "shadow_caster":
            assign(obj, visible_shadow=hide)
        elif prop == "reflection_probe":
            assign(obj, hide_probe_sphere=not hide)
        if hide:
            continue
        if prop == "water_body":
            reach = float(scene.eevee.volumetric_end) if hasattr(scene, "eevee") else 100.0
            assign(companion, location=(cam.position[0], cam.position[1], level - reach),
                    scale=(reach,) * 3)
            if companion.data.materials[0] is not None:
                water.set_effects(companion.data.materials[0].node_tree, in_use,
                                  water.BODY_NODES)
        elif prop == "reflection_probe":
            reach = float(np.linalg.norm(cam.corners[4:] - cam.position, axis=-1).max())
            location, half, clip = effects.mirror_capture(cam.position, level, bound, reach)
            assign(companion, location=location, scale=half)
            # The parallax volume (scaled by the slab) reaches `reach` upward: the water's
            # reflection vector looks the capture up as if at infinity.
            assign(companion.data, clip_start=clip, clip_end=2.0 * reach,
                    parallax_distance=reach / half[2])


def effects_in_use():
    """{effect: on}: on if on for any ocean built, since every ocean shares the water group
    whose branches are muted by it."""
    on = dict.fromkeys(effects.EFFECTS, False)
    for name, state in STATE.items():
        obj = bpy.data.objects.get(name)
        if obj is None or not (obj.projgrid.is_ocean or obj.get(STAND_IN)):
            continue
        for effect, (active, _) in (state.get("effects") or {}).items():
            on[effect] = on[effect] or active
    return on


def _refuse(state, mesh, message):
    """Record why no grid was built; our mesh (never the user's) is emptied, not left stale."""
    state.update(key=None, message=message, vertices=0, grid=None, ms=0.0, effects=None,
                 warning=None)
    if mesh is not None:
        _empty(mesh)
    return message


def empty_for_save(obj):
    """Our surface's mesh emptied and its companions hidden, as a file is saved."""
    _empty(obj.data)
    STATE.get(obj.name_full, {})["key"] = None
    for prop in COMPANIONS:
        companion = getattr(obj.projgrid, prop)
        if companion is not None and owns(companion) and local(companion):
            assign(companion, hide_render=True, hide_viewport=True)


def _empty(mesh):
    if len(mesh.vertices) or len(mesh.polygons):
        mesh.clear_geometry()
        mesh.update()


def set_topology(mesh, nx, ny, flipped=False):
    """Replace the mesh's geometry by an nx x ny grid of quads, counter-clockwise seen from
    above in the mesh's own space, or clockwise if `flipped` (an ocean object mirrored by a
    negative scale, so its faces are counter-clockwise, facing up, in the world)."""
    quads = grid_topology(nx, ny)
    if flipped:
        quads = np.ascontiguousarray(quads[:, ::-1])
    faces = len(quads)
    mesh.clear_geometry()
    mesh.vertices.add(nx * ny)
    mesh.loops.add(quads.size)
    mesh.polygons.add(faces)
    mesh.loops.foreach_set("vertex_index", quads.ravel())
    del quads
    mesh.polygons.foreach_set("loop_start", np.arange(0, 4 * faces, 4, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(faces, dtype=bool))
    mesh.update(calc_edges=True)
    uv = mesh.uv_layers.new(name=UV_MAP)
    uv.data.foreach_set("uv", corner_uv(nx, ny, flipped).ravel())
    if water.LOD_ATTRIBUTE not in mesh.attributes:
        mesh.attributes.new(water.LOD_ATTRIBUTE, "FLOAT", "POINT")


def write_mesh(mesh, result, to_local):
    """Write a GridResult into our mesh through the fast attribute path."""
    if not result.visible:
        if len(mesh.vertices):
            mesh.clear_geometry()
            mesh.update()
        return
    nx, ny = result.resolution
    flipped = np.linalg.det(to_local) < 0.0
    if (len(mesh.vertices) != nx * ny or len(mesh.polygons) != (nx - 1) * (ny - 1)
            or (mesh.loops[1].vertex_index != 1) != flipped):
        try:
            set_topology(mesh, nx, ny, flipped)
        except BaseException:
            _empty(mesh)  # never a half-built mesh
            raise
    positions = result.positions
    if not np.allclose(to_local, np.eye(3), rtol=0.0, atol=0.0):
        positions = (positions @ to_local.T.astype(np.float32)).astype(np.float32)
    mesh.attributes["position"].data.foreach_set("vector", positions.ravel())
    lod = np.minimum(result.lod, np.float32(64.0))  # finite for the shader
    mesh.attributes[water.LOD_ATTRIBUTE].data.foreach_set("value", lod)
    mesh.update()
    mesh.vertices[0].co = mesh.vertices[0].co  # refresh the bounding box after the fast path


classes = (ProjectedGridSettings,)
_register_classes, _unregister_classes = bpy.utils.register_classes_factory(classes)


def register():
    _register_classes()
    bpy.types.Object.projgrid = PointerProperty(type=ProjectedGridSettings, override=OVERRIDABLE)


def unregister():
    del bpy.types.Object.projgrid
    _unregister_classes()
    STATE.clear()
    LIVE_VIEW.clear()
    RENDERING["active"] = False
