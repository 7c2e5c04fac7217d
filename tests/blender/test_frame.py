"""A frame is gather -> plan -> apply: gathering writes nothing (run where Blender refuses any
write to its data: inside an operator's poll, as in a panel's draw), and what it gathers is
plain data the core plans without Blender."""

import bpy
import numpy as np
import pytest

from .helpers import add_camera, add_ocean

PROBE = {}


class PROJGRID_OT_test_gather(bpy.types.Operator):
    """Runs PROBE["run"] in its poll, where Blender raises on any write to ID data."""

    bl_idname = "projgrid.test_gather"
    bl_label = "Gather probe"

    @classmethod
    def poll(cls, context):
        try:
            PROBE["result"] = PROBE["run"]()
        except Exception as e:  # noqa: BLE001 (what it raised is the test's finding)
            PROBE["error"] = e
        return False


@pytest.fixture
def read_only():
    """read_only(fn): fn() run where writes to Blender data raise; returns what it returned."""
    bpy.utils.register_class(PROJGRID_OT_test_gather)

    def run(fn):
        PROBE.clear()
        PROBE["run"] = fn
        bpy.ops.projgrid.test_gather.poll()
        if "error" in PROBE:
            raise PROBE["error"]
        return PROBE["result"]

    yield run
    bpy.utils.unregister_class(PROJGRID_OT_test_gather)


def counts():
    """How many of each kind of data block the file holds."""
    return {name: len(getattr(bpy.data, name)) for name in (
        "objects", "meshes", "materials", "images", "node_groups", "collections",
        "lightprobes", "actions", "cache_files")}


def test_the_probe_refuses_writes(read_only):
    """The harness can fail: a write inside it raises."""
    add_camera(bpy.context.scene)
    camera = bpy.context.scene.camera
    with pytest.raises(AttributeError, match="not allowed"):
        read_only(lambda: setattr(camera, "location", (1.0, 2.0, 3.0)))


@pytest.mark.parametrize("render", [False, True])
def test_gathering_a_frame_writes_nothing(bridge, read_only, render):
    """Gather reads a frame of every appearance, a stand-in per instance among them (one yet
    to be made), with objects in view, a sun and a keyframed wind, into plain inputs; Blender
    refuses every write while it runs, and the file holds what it held."""
    scene = bpy.context.scene
    add_camera(scene, location=(0.0, 0.0, 4.0))
    obj = add_ocean()
    # (a keyed wind's foam is calibrated at each 5 % of its wind: seconds; the foam's settings
    # are gathered as any other's)
    obj.projgrid.foam = "OFF"
    obj.projgrid.wind_speed = 6.0
    obj.keyframe_insert("projgrid.wind_speed", frame=1)
    obj.projgrid.wind_speed = 12.0
    obj.keyframe_insert("projgrid.wind_speed", frame=40)
    bpy.ops.mesh.primitive_cube_add(location=(0.0, 30.0, 0.0))  # crossing the water in view
    scene.frame_set(2)
    sea = bpy.data.collections.new("Sea")
    sea.objects.link(obj)
    first = bpy.data.objects.new("First", None)
    first.instance_type, first.instance_collection = "COLLECTION", sea
    scene.collection.objects.link(first)
    scene.frame_set(3)  # the instance's stand-in made; the ocean's own appearance too
    second = bpy.data.objects.new("Second", None)
    second.instance_type, second.instance_collection = "COLLECTION", sea
    second.location = (0.0, 0.0, -1.0)
    scene.collection.objects.link(second)
    updates = bpy.app.handlers.depsgraph_update_post
    ours = [h for h in updates if h is bridge.handlers.depsgraph_update_post]
    for handler in ours:  # so Second's stand-in is left for the frame to make
        updates.remove(handler)
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    finally:
        updates.extend(ours)
    scene.frame_current = 7  # a frame not built yet: each appearance is gathered whole
    bridge.scene.drop_caches()  # (the update the handler would have noted)
    apps = bridge.scene.appearances(scene)
    assert len(apps) == 3
    before = counts()
    reads = read_only(lambda: [bridge.gather.frame(a, scene, depsgraph, render) for a in apps])
    assert counts() == before
    made = [r for r in reads if r.make_stand_in]
    assert len(made) == (0 if render else 1) and all(r.surface is None for r in made)
    planned = [r for r in reads if r.inputs is not None]
    assert planned and all(r.refusal is None and not r.unchanged for r in planned)
    for read in planned:
        inputs = read.inputs
        assert inputs.render == render and inputs.wind_samples is not None
        assert inputs.settings.wind_speed == pytest.approx(obj.projgrid.wind_speed)
        assert [o.name for o in inputs.facts.objects] == ["Cube"]
        assert not any(isinstance(getattr(inputs, f), bpy.types.ID)
                       for f in inputs.__dataclass_fields__)


def test_the_frame_is_the_three_steps(bridge, extension):
    """The frame the handlers build is apply(gather, plan): the mesh written is the plan's grid
    for the gathered inputs, planned again here by the core alone."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    scene.frame_set(4)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    bridge.state.RUNTIME.state(obj).key = None
    (app,) = bridge.scene.appearances(scene)
    read = bridge.gather.frame(app, scene, depsgraph, False)
    plan = extension.projgrid_addon.frame_plan.plan(read.inputs)
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.attributes["position"].data.foreach_get("vector", co)
    assert np.array_equal(co.reshape(-1, 3), plan.result.positions)


def test_many_moving_objects_are_read_at_once(bridge):
    """The viewport reads every object's box at once (foreach_get over the scene's objects), as
    a render reads each alone; a frame that moves more of them than scene.MANY_UPDATES reads
    them all again, so the effects' facts follow them."""
    scene = bpy.context.scene
    add_camera(scene)
    add_ocean()
    rng = np.random.default_rng(5)
    count = bridge.scene.MANY_UPDATES + 36
    for i in range(count):
        bpy.ops.mesh.primitive_cube_add(location=(*rng.uniform(-40.0, 40.0, 2), -6.0),
                                        rotation=rng.uniform(0.0, 3.0, 3),
                                        scale=rng.uniform(0.3, 2.0, 3))
        cube = bpy.context.active_object
        cube.keyframe_insert("location", frame=1)
        cube.location.z = 6.0 + i * 0.01
        cube.keyframe_insert("location", frame=11)
    scene.frame_set(1)
    cache = bridge.scene.valid_cache(scene)
    objects = bridge.objects
    cache.boxes = cache.boxes or objects.ObjectBoxes(scene, False)
    for frame in (1, 6):
        scene.frame_set(frame)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        alone = objects.ObjectBoxes(scene, True, depsgraph)
        assert len(alone.boxes) == count
        assert np.allclose(cache.boxes.boxes, alone.boxes, atol=1e-5)


def test_a_moved_object_is_read_again_beside_our_own_updates(bridge):
    """An update that moves the user's object and touches ours too (the ocean, whose box is not
    kept) reads the object's box again, and says it may matter."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    bpy.ops.mesh.primitive_cube_add(location=(0.0, 30.0, 0.0))
    cube = bpy.context.active_object
    scene.frame_set(2)
    boxes = bridge.objects.ObjectBoxes(scene, False)
    cube.location.x += 50.0
    bpy.context.view_layer.update()
    assert boxes.refresh([obj, cube])
    row = boxes.index[cube.session_uid]
    assert boxes.boxes[row, :, 0].min() == pytest.approx(49.0, abs=1e-4)


def test_a_collection_relinked_beside_many_moving_objects_is_followed(bridge):
    """A frame that moves more objects than scene.MANY_UPDATES and relinks a collection (the
    ocean put into one an instancer shows, no count changing) finds the ocean's new
    appearance: a stand-in per place it shows."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    for i in range(bridge.scene.MANY_UPDATES + 16):
        bpy.ops.mesh.primitive_cube_add(location=(i * 3.0 - 100.0, 60.0, -10.0))
        cube = bpy.context.active_object
        cube.keyframe_insert("location", frame=1)
        cube.location.z = -5.0
        cube.keyframe_insert("location", frame=10)
    sea = bpy.data.collections.new("Sea")
    instancer = bpy.data.objects.new("Instancer", None)
    instancer.instance_type, instancer.instance_collection = "COLLECTION", sea
    instancer.location = (0.0, 0.0, 3.0)
    scene.collection.objects.link(instancer)
    scene.frame_set(1)
    assert len(bridge.scene.appearances(scene)) == 1
    sea.objects.link(obj)
    scene.frame_set(2)
    assert len(bridge.scene.appearances(scene)) == 2
    assert sum(1 for o in scene.objects if o.get(bridge.scene.STAND_IN)) == 2


def test_a_camera_keyed_along_its_heading_alone_dollies(bridge):
    """The frame's inputs say the camera dollies (moves along its heading alone, its
    orientation, height and lens the same at every time: the residual foam's past on
    canonical cameras, past_grid.py) while its keys move it so (Location and Rotation keyed,
    its height and rotation held); a still camera does not, nor do keys that slide it sideways,
    lift, turn or zoom it, a constraint, a driver, or a parent."""
    scene = bpy.context.scene
    cam = add_camera(scene)  # looking along +y
    obj = add_ocean()
    (app,) = bridge.scene.appearances(scene)

    def dollies():
        scene.frame_set(24)
        bridge.state.RUNTIME.state(obj).key = None
        depsgraph = bpy.context.evaluated_depsgraph_get()
        return bridge.gather.frame(app, scene, depsgraph, False).inputs.dolly

    def keys(block, path, values, frames=(1, 48)):
        for frame, value in zip(frames, values, strict=True):
            setattr(block, path, value)
            block.keyframe_insert(path, frame=frame)

    def dolly():
        keys(cam, "location", [(0.0, 0.0, z), (0.0, 30.0, z), (0.0, 50.0, z)], (1, 20, 48))
        keys(cam, "rotation_euler", [turn, turn])
    def slides():  # x level through the keys, then extrapolated along a sloping handle
        (curve,) = [c for c in bridge.scene.bag_curves(cam)
                    if c.data_path == "location" and c.array_index == 0]
        key = curve.keyframe_points[-1]
        key.handle_left_type = key.handle_right_type = "FREE"
        key.handle_left, key.handle_right = (47.0, 0.0), (49.0, 0.5)
        curve.extrapolation = "LINEAR"
        curve.update()
    z, turn = cam.location.z, tuple(cam.rotation_euler)
    assert not dollies()
    keys(cam, "location", [(0.0, 0.0, z), (0.0, 0.0, z)])
    assert not dollies()
    dolly()
    assert dollies()
    for moved in (lambda: keys(cam, "location", [(0.0, 0.0, z), (0.0, 50.0, z + 3.0)]),
                  lambda: keys(cam, "location", [(0.0, 0.0, z), (1.0, 50.0, z)], (1, 30)),
                  lambda: keys(cam, "rotation_euler", [turn, (*turn[:2], turn[2] + 0.3)]),
                  lambda: keys(cam.data, "lens", [50.0, 35.0]), slides,
                  lambda: cam.driver_add("scale", 0),
                  lambda: cam.constraints.new("TRACK_TO")):
        moved()
        assert not dollies()
        cam.animation_data_clear()
        cam.data.animation_data_clear()
        cam.constraints.clear()
        dolly()
        assert dollies()
    cam.parent = bpy.data.objects.new("Rig", None)
    assert not dollies()



def test_a_value_that_did_not_change_is_not_written_again(extension):
    """shaders.nodes.assign writes only changes: Blender keeps a socket's value in float32, so
    one that did not change reads back off by up to half its last place (the gale's Pixel Log,
    -6.8387624, by 1.2e-7: written every frame, each write tagging the material, 1 ms a
    frame); a change of one float32 step is still written."""
    class Socket:  # a float property as Blender keeps it: in single precision
        writes, _value = 0, 0.0

        @property
        def default_value(self):
            return self._value

        @default_value.setter
        def default_value(self, value):
            Socket.writes += 1
            self._value = float(np.float32(value))

    socket = Socket()
    for value in (-6.838762407495186, 32.277787223740745, 1e4 + 0.3):
        extension.shaders.nodes.assign(socket, default_value=value)
        writes = Socket.writes
        extension.shaders.nodes.assign(socket, default_value=value)
        assert Socket.writes == writes, value
        step = float(np.spacing(np.float32(value)))
        extension.shaders.nodes.assign(socket, default_value=socket.default_value + step)
        assert Socket.writes == writes + 1, value
