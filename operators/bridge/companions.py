"""Our objects beside an ocean: stand-ins and companions, made, shown, placed and removed.

A *stand-in* draws an ocean we may not write (linked, a library override) or that shows more
than once (one stand-in per instance): a local object of ours with its own mesh and material.
*Companions* serve the effects: the water body (a volume under the camera), the shadow caster
(the ocean's mesh drawn again with our caustic shadow material) and the reflection probe. A
surface (an ocean drawing itself, or a stand-in) points to its companions from its settings.
Everything here writes only objects and data of ours.

Over 300 lines on purpose: stand-ins and companions share one lifecycle (made, followed,
mended, removed) and the rule that only our own data is written.
"""

import bpy
import numpy as np

from ...projgrid_addon import optics
from ...shaders import materials as shader_materials
from ...shaders import water
from ...shaders.nodes import TAG, assign
from . import baked, material_inputs
from .mesh import empty, write_puffs
from .scene import COMPANION, COMPANIONS, STAND_IN, hidden_in, local, owns
from .state import RUNTIME

# ---- Stand-ins ---------------------------------------------------------------------------------

def ours_here(obj):
    """An object of ours local to this file (a library's objects of ours are never touched)."""
    return obj is not None and owns(obj) and local(obj)


def stand_in(app, scene, create):
    """Our local object drawing `app` (made if missing and `create`), or None. It goes in the
    scene's own collection (not the ocean's, which may itself be instanced) and follows the
    ocean's visibility and layer flags itself (`follow_visibility`)."""
    key = app.key
    obj = bpy.data.objects.get((RUNTIME.stand_ins.get(key, ""), None))
    if obj is None or obj.get(STAND_IN) != key:
        obj = next((o for o in bpy.data.objects if o.get(STAND_IN) == key and ours_here(o)),
                   None)
    if obj is None and create:
        name = f"{app.ocean.name} Sea"
        mesh = bpy.data.meshes.new(name)
        mesh[TAG] = True
        source = app.ocean.data.materials[0] if app.ocean.data and len(
            app.ocean.data.materials) else None
        mesh.materials.append(material_inputs.adopt_material(source))
        obj = bpy.data.objects.new(name, mesh)
        obj[TAG] = True
        obj[STAND_IN] = key
        obj.projgrid.source = app.ocean
        obj.hide_select = True
        if hasattr(obj, "cycles"):
            obj.cycles.use_deform_motion = False
        scene.collection.objects.link(obj)
        ensure_companions(obj)
    if obj is not None:
        RUNTIME.stand_ins[key] = obj.name_full
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
        candidates = [bpy.data.objects.get((name, None)) for name in RUNTIME.stand_ins.values()]
    stale = [o for o in candidates if ours_here(o) and o.get(STAND_IN)
             and scene in o.users_scene
             and (o.projgrid.source is None or o[STAND_IN] not in needed)]
    for obj in stale:
        RUNTIME.surfaces.pop(obj.session_uid, None)
        RUNTIME.stand_ins.pop(obj[STAND_IN], None)
        for companion in companions_of(obj):
            if local(companion):
                _remove_object(companion)
        _remove_object(obj)
    return len(stale)


# ---- Companions --------------------------------------------------------------------------------

def _new_companion(obj, prop, name):
    """The data of a new companion: a closed unit box, the surface's own mesh (the caster draws
    it again with our shadow material, linked to the object), a sphere light probe with a
    box influence and a parallax volume set per frame (optics.mirror_capture), or the spray's
    mesh of puffs (drawn as points by our geometry nodes)."""
    if prop == "shadow_caster":
        return obj.data
    if prop == "spray_cloud":  # its vertices are the puffs, written each frame
        data = bpy.data.meshes.new(name)
        data.materials.append(shader_materials.spray_material())
    elif prop == "water_body":
        data = bpy.data.meshes.new(name)
        data.from_pydata([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], [],
                         [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
                          (1, 5, 7, 3)])
        data.materials.append(shader_materials.body_material(optics.ABSORPTION,
                                                  optics.GODRAY_TILE_TEXELS))
    else:
        data = bpy.data.lightprobes.new(name, "SPHERE")
        data.influence_type, data.influence_distance, data.falloff = "BOX", 1.0, 0.0
        data.use_custom_parallax, data.parallax_type = True, "BOX"
    data[TAG] = True
    return data


def ensure_companions(obj):
    """Our water body, shadow caster and reflection probe for a surface, made hidden if missing
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
        if prop in ("water_body", "spray_cloud"):
            companion.visible_shadow = False
        if prop == "spray_cloud":
            companion.modifiers.new(water.SPRAY_POINTS, "NODES").node_group = (
                shader_materials.spray_points())
        if prop == "shadow_caster":
            companion.parent = obj
            for slot in companion.material_slots:
                slot.link = "OBJECT"
                slot.material = shader_materials.shadow_material(optics.CAUSTIC_MEAN)
            for ray in ("camera", "diffuse", "glossy", "transmission", "volume_scatter"):
                setattr(companion, f"visible_{ray}", False)
        collection.objects.link(companion)
        setattr(settings, prop, companion)


def companions_of(obj):
    return [c for c in (getattr(obj.projgrid, p) for p in COMPANIONS)
            if c is not None and owns(c) and c != obj]


def follow_visibility(surface, app, seen, render, view_layer, relink):
    """A stand-in and the companions follow their ocean where it shows (`seen`:
    gather.Visibility): hidden with it (in renders by the render's own evaluation, in the
    viewport by the objects' flags and, in `view_layer` alone, its eye), a holdout and
    indirect-only with it (its collections' flags included). The ocean's own flags are the
    user's and are never written. Companions share the surface's collections, so they also
    share its view-layer exclusion (checked when `relink`: the collections may have changed)."""
    ours = ([surface] if surface is not app.ocean else []) + companions_of(surface)
    for obj in ours:
        assign(obj, is_holdout=seen.holdout)
        if obj is surface:
            assign(obj, hide_render=seen.hidden_render, hide_viewport=seen.hidden_viewport,
                   visible_camera=not seen.indirect)
        else:  # only hidden here; place_companions shows what an effect needs
            if seen.hidden_render:
                assign(obj, hide_render=True)
            if seen.hidden_viewport:
                assign(obj, hide_viewport=True)
        if not render and hidden_in(obj, view_layer) != seen.eye:
            try:
                obj.hide_set(seen.eye, view_layer=view_layer)
            except RuntimeError:  # not in this view layer
                pass
        if relink and obj is not surface and (
                set(obj.users_collection) != set(surface.users_collection)):
            _link_like(obj, surface)


def hide_companions(obj):
    """The companions of an ocean whose sea its stand-ins draw, or of one being saved: hidden,
    not left as they were (the spray emptied too)."""
    for companion in companions_of(obj):
        if local(companion):
            assign(companion, hide_render=True, hide_viewport=True)
            if companion == obj.projgrid.spray_cloud and owns(companion.data):
                empty(companion.data)


def _link_like(obj, model):
    """Put our `obj` in exactly the local collections `model` is in."""
    for collection in model.users_collection:
        if collection not in obj.users_collection and local(collection):
            collection.objects.link(obj)
    for collection in obj.users_collection:
        if collection not in model.users_collection:
            collection.objects.unlink(obj)


def place_companions(obj, cam, level, bound, on, in_use, volume_reach, hidden=(False, False)):
    """Show each companion only while an effect needs it (hidden, it costs nothing) and its
    ocean is not `hidden` (in renders, in the viewport): the water body centred under the
    camera at the water level and `volume_reach` wide (as far as EEVEE draws volumes), the
    reflection probe at the camera mirrored in the water, reaching as far as the camera sees."""
    # The water never shadows itself: its waves' shadowing of the sun's glint is the
    # reflection's own (the microfacets' masking); a shadow map of the waves on the waves draws
    # blocks into the glitter path. Only the caster shadows what is below.
    assign(obj, visible_shadow=False)
    for prop, (_, needed_by) in COMPANIONS.items():
        companion = getattr(obj.projgrid, prop)
        if companion is None or not owns(companion):
            continue
        hide = not any(on[e] for e in needed_by)
        assign(companion, hide_render=hide or hidden[0], hide_viewport=hide or hidden[1])
        if prop == "reflection_probe":
            assign(obj, hide_probe_sphere=not hide)
        if hide:
            continue
        if prop == "water_body":
            reach = volume_reach
            assign(companion, location=(cam.position[0], cam.position[1], level - reach),
                   scale=(reach,) * 3)
            if companion.data.materials[0] is not None:
                material_inputs.set_effects(companion.data.materials[0].node_tree, in_use,
                                  water.BODY_NODES)
        elif prop == "reflection_probe":
            reach = float(np.linalg.norm(cam.corners[4:] - cam.position, axis=-1).max())
            location, half, clip = optics.mirror_capture(cam.position, level, bound, reach)
            assign(companion, location=location, scale=half)
            # The parallax volume (scaled by the slab) reaches `reach` upward: the water's
            # reflection vector looks the capture up as if at infinity.
            assign(companion.data, clip_start=clip, clip_end=2.0 * reach,
                   parallax_distance=reach / half[2])


def write_spray(obj, puffs, level, faces=False, air=None):
    """The spray companion's mesh: a vertex per puff (spray.spray: positions, radii,
    opacities; None: none) with its radius and opacity (with `faces`, a bake's triangle per
    puff: mesh.write_puffs), the object under the puffs' mean at the sea's `level` (so float32
    offsets stay small); `air`: the haze its material reads (water.SPRAY_AIR: the extinction
    per metre, the overcast), or None to leave it."""
    cloud = obj.projgrid.spray_cloud
    if cloud is None or not owns(cloud) or not owns(cloud.data):
        return
    if air is not None:
        shader_materials.spray_points()  # a file's older spray material rebuilt in place
    changed = False
    for name, value in zip(water.SPRAY_AIR, air or (), strict=False):
        if abs(cloud.get(name, -1.0) - value) > 1e-9:
            cloud[name], changed = float(value), True
    if changed:  # a custom property's write alone does not reach the shader's copy
        cloud.update_tag()
    if puffs is None or len(puffs[0]) == 0:
        empty(cloud.data)
        return
    positions, radii, opacities = puffs
    centre = np.round(positions[:, :2].mean(axis=0).astype(np.float64))
    assign(cloud, location=(float(centre[0]), float(centre[1]), level),
           rotation_euler=(0.0, 0.0, 0.0), scale=(1.0, 1.0, 1.0))
    local = (positions - np.array([centre[0], centre[1], level])).astype(np.float32)
    write_puffs(cloud.data, local, dict(zip(water.SPRAY_ATTRIBUTES, (radii, opacities),
                                            strict=True)), faces)


# ---- The render mesh ---------------------------------------------------------------------------

def use_render_mesh(surface):
    """While a render runs, the surface (and its shadow caster) draw a second mesh of ours, so
    the render grid's topology is built once and kept from render to render, and the viewport
    grid is there again untouched afterwards (`use_viewport_mesh`)."""
    viewport = surface.data
    if not owns(viewport) or not local(viewport) or surface.session_uid in RUNTIME.swapped:
        return
    mesh = surface.projgrid.render_mesh
    taken = {s.data for s, _ in RUNTIME.swapped.values()}  # a duplicate's copied pointer
    if mesh is None or not owns(mesh) or not local(mesh) or mesh in taken:
        mesh = bpy.data.meshes.new(viewport.name + " Render")
        mesh[TAG] = True
        surface.projgrid.render_mesh = mesh
    if list(mesh.materials) != list(viewport.materials):
        mesh.materials.clear()
        for material in viewport.materials:
            mesh.materials.append(material)
    RUNTIME.swapped[surface.session_uid] = (surface, viewport)
    _draw(surface, viewport, mesh)


def use_viewport_mesh():
    """After a render: every surface draws its viewport mesh again."""
    for surface, viewport in list(RUNTIME.swapped.values()):
        try:
            _draw(surface, surface.data, viewport)
        except ReferenceError:  # deleted while rendering
            pass
    RUNTIME.swapped.clear()


def mend_render_meshes():
    """After a load: a surface saved in the middle of a render drew its render mesh; that mesh
    is its viewport mesh from now on (emptied; rebuilt at the next update)."""
    for obj in bpy.data.objects:
        mesh = obj.projgrid.render_mesh if obj.type == "MESH" else None
        if mesh is not None and obj.data == mesh and owns(mesh) and local(obj):
            obj.projgrid.render_mesh = None
            empty(mesh)


def _draw(surface, old, new):
    surface.data = new
    caster = surface.projgrid.shadow_caster
    if caster is not None and owns(caster) and caster.data == old:
        caster.data = new
        for slot in caster.material_slots:
            slot.link = "OBJECT"
            slot.material = shader_materials.shadow_material(optics.CAUSTIC_MEAN)


# ---- Removal, materials, saving ----------------------------------------------------------------

def _remove_object(obj):
    """Delete our object, and its data when it is ours and nothing else uses it."""
    data, obj_type = obj.data, obj.type
    bpy.data.objects.remove(obj)
    if data is not None and owns(data) and data.users == 0:
        kind = bpy.data.lightprobes if obj_type == "LIGHT_PROBE" else bpy.data.meshes
        kind.remove(data)


def remove_orphan_companions():
    """Delete our local stand-ins whose ocean was deleted, then our local companions no ocean
    or stand-in points to any more, with their data when nothing else uses it; returns how
    many."""
    gone = [o for o in bpy.data.objects
            if o.get(STAND_IN) and ours_here(o) and o.projgrid.source is None]
    for obj in gone:
        _remove_object(obj)
    kept = {getattr(o.projgrid, prop) for o in bpy.data.objects
            if o.projgrid.is_ocean or o.get(STAND_IN) for prop in COMPANIONS}
    orphans = [o for o in bpy.data.objects
               if o.get(COMPANION) and ours_here(o) and o not in kept]
    for obj in orphans:
        _remove_object(obj)
    return len(gone) + len(orphans)


def own_material(surface):
    """The surface's water material is its own (material_inputs.own_material), without the keys and
    image sequences of a bake the material it was copied from plays (a duplicate's)."""
    copy = material_inputs.own_material(surface.data)
    if copy is not None:
        if not baked.is_baked(surface):  # a baked one plays the keys
            baked.drop_bake(copy)


def empty_for_save(obj):
    """Our surface's meshes (the spray's too) emptied and its companions hidden, as a file is
    saved."""
    empty(obj.data)
    if obj.projgrid.render_mesh is not None and owns(obj.projgrid.render_mesh):
        empty(obj.projgrid.render_mesh)
    state = RUNTIME.peek(obj)
    if state is not None:
        state.key = None
    hide_companions(obj)
