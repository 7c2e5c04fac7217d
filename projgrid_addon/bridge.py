"""Where Blender meets the core: the ocean's settings, its camera, its mesh and material inputs.

The only module of the core that imports bpy. Everything here reads Blender data, calls the core,
and writes our own ocean mesh and material; it never writes anything of the user's.
"""

import time

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

from ..shaders import water
from ..shaders.nodes import TAG, assign
from . import Camera, HeightField, build_grid, effects, grid_topology, grid_uv
from .projected_grid import check_resolution

UV_MAP = "ProjectorUV"

# Per-object runtime state, keyed by the object's name_full: stats for the panel, the message of
# the last refused rebuild, and the signature of the last build (to skip identical rebuilds).
STATE = {}
# Set by the render handlers; the live preview steps aside while it is true.
RENDERING = {"active": False}
# The 3D view the live preview follows: {"view": 4x4, "proj": 4x4} or empty.
LIVE_VIEW = {}


def _settings_changed(self, context):
    """Rebuild at once with the values just set (the evaluated copy is updated only later)."""
    obj = self.id_data
    if context.scene is not None and obj.name in context.scene.objects:
        update_ocean(obj, context.scene, context.evaluated_depsgraph_get(), settings=self)


def _mode(effect, description):
    return EnumProperty(
        name=effect.replace("_", " ").title(), default="AUTO", update=_settings_changed,
        description=description,
        items=(("AUTO", "Auto", "On when the scene calls for it, decided each frame"),
               ("ON", "On", "Always on"), ("OFF", "Off", "Always off: costs nothing")))


def _active_effects(self):
    """Bit set of the effects on for the last built frame (read-only `active_effects`)."""
    decisions = STATE.get(self.id_data.name_full, {}).get("effects") or {}
    return sum(1 << i for i, e in enumerate(effects.EFFECTS) if decisions.get(e, (False,))[0])


def _int(name, description, default, lo, hi, soft_hi=None):
    return IntProperty(name=name, description=description, default=default, min=lo, max=hi,
                       soft_max=soft_hi or hi, update=_settings_changed)


def _float(name, description, default, lo, hi, soft_hi, unit="NONE", **kw):
    return FloatProperty(name=name, description=description, default=default, min=lo, max=hi,
                         soft_max=soft_hi, unit=unit, update=_settings_changed, **kw)


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
        name="Noise", default="FAST", update=_settings_changed,
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
    return [obj for obj in scene.objects if obj.type == "MESH" and obj.projgrid.is_ocean]


def owns(id_block):
    return id_block is not None and bool(id_block.get(TAG))


def render_size(scene):
    r = scene.render
    pct = r.resolution_percentage / 100.0
    return (max(1, round(r.resolution_x * pct)), max(1, round(r.resolution_y * pct)),
            r.pixel_aspect_x, r.pixel_aspect_y)


def camera_for(scene, depsgraph, render):
    """(view, proj) of the scene camera as rendered (ValueError with a user message if none)."""
    cam = scene.camera
    if cam is None:
        raise ValueError("the scene has no camera (set one, or use Live Preview)")
    cam_eval = cam.evaluated_get(depsgraph)
    if cam_eval.type == "CAMERA" and cam_eval.data.type == "PANO":
        raise ValueError(f"camera {cam.name!r} is panoramic; the projected grid needs a "
                         "perspective or orthographic camera")
    x, y, sx, sy = render_size(scene)
    proj = cam_eval.calc_matrix_camera(depsgraph, x=x, y=y, scale_x=sx, scale_y=sy)
    view = cam_eval.matrix_world.normalized().inverted()
    return np.array(view, dtype=np.float64), np.array(proj, dtype=np.float64)


def scene_time(scene):
    """Seconds at the current (sub)frame."""
    r = scene.render
    return (scene.frame_current + scene.frame_subframe) * r.fps_base / r.fps


def update_ocean(obj, scene, depsgraph, render=None, view=None, settings=None):
    """Rebuild `obj`'s grid for the current frame; returns the refusal message or None.

    `render` defaults to whether `depsgraph` is a render depsgraph: renders use the render camera
    and resolution, the viewport the live preview's view if one runs, else the scene camera.
    Settings are read from the evaluated object, so animated values are honoured in renders,
    unless `settings` are given (a settings edit passes the values just set).
    """
    state = STATE.setdefault(obj.name_full, {})
    if render is None:
        render = depsgraph.mode == "RENDER"
    if not owns(obj.data):
        return _refuse(state, None, "the ocean's mesh was replaced; it is left untouched "
                       "(Add Ocean makes a new one)")
    mesh = obj.data
    obj_eval = obj.evaluated_get(depsgraph)
    settings = settings or obj_eval.projgrid
    try:
        if render:
            res = (settings.render_resolution_x, settings.render_resolution_y)
        else:
            res = (settings.resolution_x, settings.resolution_y)
        res = check_resolution(res)
        if view is None and not render and LIVE_VIEW:
            view = (LIVE_VIEW["view"], LIVE_VIEW["proj"])
        camera = view if view is not None else camera_for(scene, depsgraph, render)
        world = np.array(obj_eval.matrix_world, dtype=np.float64)
        linear = world[:3, :3]
        if abs(np.linalg.det(linear)) < 1e-12:
            raise ValueError("the ocean object's scale is zero")
        t = scene_time(scene)
        hf = height_field(settings)
        cam = Camera(*camera)
        sun = water.sun_lamp(scene, depsgraph)  # once per frame: the facts and the glint
        facts = scene_facts(obj, scene, sun, cam, world[2, 3], hf, settings, render)
        key = (render, res, np.asarray(camera[0]).tobytes(), np.asarray(camera[1]).tobytes(),
               world.tobytes(), t, tuple(getattr(settings, p) for p in SETTINGS),
               mesh.session_uid, facts.key())
        if key == state.get("key"):
            return None
        start = time.perf_counter()
        result = build_grid(cam, hf, level=world[2, 3], time=t, resolution=res,
                            projector_elevation=settings.projector_elevation,
                            origin=world[:3, 3])
        decisions = effects.decide({e: getattr(settings, e) for e in effects.EFFECTS}, facts)
        on = {e: d[0] for e, d in decisions.items()}
        write_mesh(mesh, result, np.linalg.inv(linear))
        write_foam(mesh, result, hf, settings, t, on, facts, world[2, 3])
        write_caustics(mesh, result, facts, on)
        write_godrays(obj, hf, t, cam, world[2, 3], facts, on)
    except ValueError as e:
        return _refuse(state, mesh, str(e))
    state.update(key=key, message=None, vertices=len(result.positions), grid=result,
                 ms=(time.perf_counter() - start) * 1e3, effects=decisions,
                 shader_octaves=result.shader_octaves, resolution=res, render=render)
    in_use = effects_in_use()
    water.update_inputs(obj, sun, hf, result.shader_octaves, t, in_use)
    if not render and not RENDERING["active"]:
        ensure_companions(obj)
    place_companions(obj, cam, world[2, 3], hf.bound, on, scene, in_use)
    return None


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


def remove_orphan_companions():
    """Delete our companions no ocean points to any more (its ocean was deleted), with their
    data when nothing else uses it; returns how many."""
    kept = {getattr(o.projgrid, prop) for o in bpy.data.objects if o.projgrid.is_ocean
            for prop in COMPANIONS}
    orphans = [o for o in bpy.data.objects if o.get(COMPANION) and owns(o) and o not in kept]
    for obj in orphans:
        data, obj_type = obj.data, obj.type
        bpy.data.objects.remove(obj)
        if data is not None and owns(data) and data.users == 0:
            kind = bpy.data.lightprobes if obj_type == "LIGHT_PROBE" else bpy.data.meshes
            kind.remove(data)
    return len(orphans)


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


def place_companions(obj, cam, level, bound, on, scene, in_use):
    """Show each companion only while an effect needs it (hidden, it costs nothing): the water
    body centred under the camera at the water level and as wide as EEVEE draws volumes, the
    reflection probe at the camera mirrored in the water, reaching as far as the camera sees."""
    for prop, (_, needed_by) in COMPANIONS.items():
        companion = getattr(obj.projgrid, prop)
        if companion is None or not owns(companion):
            continue
        hide = not any(on[e] for e in needed_by)
        assign(companion, hide_render=hide, hide_viewport=hide)
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
        if obj is None or not obj.projgrid.is_ocean:
            continue
        for effect, (active, _) in (state.get("effects") or {}).items():
            on[effect] = on[effect] or active
    return on


def _refuse(state, mesh, message):
    """Record why no grid was built; our mesh (never the user's) is emptied, not left stale."""
    state.update(key=None, message=message, vertices=0, grid=None, ms=0.0, effects=None)
    if mesh is not None and len(mesh.vertices):
        mesh.clear_geometry()
    return message


def set_topology(mesh, nx, ny):
    """Replace the mesh's geometry by an nx x ny grid of quads (built once per resolution)."""
    quads = grid_topology(nx, ny)
    mesh.clear_geometry()
    mesh.vertices.add(nx * ny)
    mesh.loops.add(quads.size)
    mesh.polygons.add(len(quads))
    mesh.loops.foreach_set("vertex_index", quads.ravel())
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(quads), dtype=bool))
    mesh.update(calc_edges=True)
    uv = mesh.uv_layers.new(name=UV_MAP)
    uv.data.foreach_set("uv", grid_uv(nx, ny)[quads.ravel()].ravel())
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
    if len(mesh.vertices) != nx * ny or len(mesh.polygons) != (nx - 1) * (ny - 1):
        set_topology(mesh, nx, ny)
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
    bpy.types.Object.projgrid = PointerProperty(type=ProjectedGridSettings)


def unregister():
    del bpy.types.Object.projgrid
    _unregister_classes()
    STATE.clear()
    LIVE_VIEW.clear()
    RENDERING["active"] = False
