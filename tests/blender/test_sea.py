"""The spectral sea in Blender: sea states, waves that travel with the wind, choppy crests,
foam from the surface; and the Blender layer's edge cases around them."""

import math
import threading
import time

import bpy
import numpy as np
import pytest

from .helpers import add_camera, add_ocean, positions


def test_sea_state_sets_the_wind_fetch_chop_and_swell(sea, extension):
    s = sea.projgrid
    sea_states = extension.projgrid_addon.sea_states
    for force in (0, 4, 8, 10):
        bpy.ops.projgrid.sea_state(beaufort=force)
        want = sea_states.sea_state(force)
        assert s.wind_speed == pytest.approx(want.wind_speed)
        assert s.fetch == pytest.approx(want.fetch, rel=1e-6)
        assert s.choppiness == pytest.approx(want.choppiness)
        assert s.swell_height == pytest.approx(want.swell_height)
    assert s.fetch > 0.0 and s.choppiness == pytest.approx(1.0)  # a storm over its fetch
    bpy.ops.projgrid.sea_state(beaufort=13)  # beyond the scale: Blender clamps it, to 10
    assert s.wind_speed == pytest.approx(sea_states.sea_state(10).wind_speed)
    # The hand-set noise (From Wind off) gets the preset's sea at the noise's own octaves,
    # roughness and spectrum, not at the defaults'.
    s.octaves, s.roughness, s.spectrum = 4, 0.8, "PIERSON_MOSKOWITZ"
    bpy.ops.projgrid.sea_state(beaufort=6)
    want = sea_states.sea_state(6)
    height = sea_states.noise_waves(want.wind_speed, want.fetch, "PIERSON_MOSKOWITZ", 4, 0.8)
    assert (s.amplitude, s.wave_scale) == pytest.approx(height, rel=1e-6)
    assert s.amplitude != pytest.approx(sea_states.noise_waves(want.wind_speed, want.fetch)[0])


def test_the_wind_raises_the_spectral_sea(sea):
    heights = []
    for force in (2, 5, 8):
        bpy.ops.projgrid.sea_state(beaufort=force)
        heights.append(float(np.ptp(positions(sea.data)[:, 2])))
    assert heights[0] < heights[1] < heights[2]


def test_a_keyed_wind_keeps_its_tiles(sea, bridge):
    """Wind speed keyframed 8 -> 10 m/s: every frame's sea is laid out for the keyed span
    (scene.wind_span, a function of the keyframes, not of the frame), so its tiles stay and
    only their heights follow the wind; unkeyed, the span is gone."""
    s, scene = sea.projgrid, bpy.context.scene
    s.foam = "OFF"  # the tiles' layout alone: no whitecaps calibrated for each frame's seas
    s.wind_speed = 8.0
    s.keyframe_insert("wind_speed", frame=1)
    s.wind_speed = 10.0
    s.keyframe_insert("wind_speed", frame=49)
    assert bridge.scene.wind_span(sea) == (8.0, 10.0)
    tiles = []
    for frame in (2, 17, 33, 48):
        scene.frame_set(frame)
        evaluated = sea.evaluated_get(bpy.context.evaluated_depsgraph_get()).projgrid
        assert bridge.scene.read_settings(evaluated).wind_span == (8.0, 10.0)
        source = bridge.scene.height_field(evaluated)
        assert source.state.wind_speed == pytest.approx(evaluated.wind_speed)
        tiles.append([(c.size, c.turn) for c in source.cascades])
    assert 8.0 < sea.evaluated_get(bpy.context.evaluated_depsgraph_get()).projgrid.wind_speed
    assert all(t == tiles[0] for t in tiles)
    sea.animation_data_clear()
    assert bridge.scene.wind_span(sea) is None


def test_a_keyed_wind_s_coming_seas_are_calibrated_ahead(sea, bridge, extension, monkeypatch):
    """Under a keyed wind the viewport's frame hands the worker the wind at the coming seconds
    (read from its curve), and asks it for (reserves) the whitecaps' calibrations of those
    winds' lattice seas too, not only of the seas about the wind now (the making itself, the
    same for any sea: test_playing_calibrates_the_coming_seconds_foam_ahead)."""
    foam, s, scene = extension.projgrid_addon.foam, sea.projgrid, bpy.context.scene
    s.wind_speed = 8.0
    s.keyframe_insert("wind_speed", frame=1)
    s.wind_speed = 14.0
    s.keyframe_insert("wind_speed", frame=73)
    handed, reserved = [], []
    calibrate, reserve = bridge.ahead.calibrate, foam.CALIBRATIONS.reserve
    monkeypatch.setattr(bridge.ahead, "calibrate", lambda *a: (handed.append(a), calibrate(*a)))
    monkeypatch.setattr(foam.CALIBRATIONS, "reserve", lambda sea_, keys: (
        reserved.append(sea_.state.wind_speed), reserve(sea_, keys))[1])
    # what is asked of the worker, not its making: each reserved calibration handed back
    monkeypatch.setattr(bridge.ahead, "_make", lambda twin, sea_, key: foam.CALIBRATIONS.release(
        sea_, key))
    scene.frame_set(13)  # 0.54 s in: the coming seconds are 1 and 2 (frames 24 and 48)
    bridge.ahead.finish()
    curve = next(c for c in bridge.scene.bag_curves(sea) if c.data_path == "projgrid.wind_speed")
    winds = handed[-1][3]
    assert winds == pytest.approx((curve.evaluate(24.0), curve.evaluate(48.0)), rel=1e-6)
    now = {w for w, _ in extension.projgrid_addon.cascade.wind_lattice(handed[-1][2])}
    later = {w for w, _ in extension.projgrid_addon.cascade.wind_lattice(winds[1])}
    assert later - now and (later - now) <= set(reserved)  # the winds of second 2's seas


def test_the_wind_raises_the_noise_from_wind(bridge, extension):
    """With From Wind (Add Ocean's), the noise's height and wavelength are the wind's sea's
    (sea_states.noise_waves), the wind keyframed too; set by hand, the wind leaves them."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    s = obj.projgrid
    s.height_source = "PERLIN"
    assert s.noise_from_wind
    for frame, wind in ((1, 5.0), (10, 10.0)):
        s.wind_speed = wind
        s.keyframe_insert("wind_speed", frame=frame)
    spread, used = [], []
    for frame in (1, 10):
        scene.frame_set(frame)
        spread.append(float(positions(obj.data)[:, 2].std()))
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).projgrid
        hf = bridge.scene.height_field(evaluated)
        used.append((hf.amplitude, hf.wave_scale))
    noise_waves = extension.projgrid_addon.sea_states.noise_waves
    assert used == [pytest.approx(noise_waves(5.0)), pytest.approx(noise_waves(10.0))]
    assert spread[1] > 2.0 * spread[0]  # Hs grows as U^2
    s.noise_from_wind = False
    assert bridge.scene.height_field(s).amplitude == pytest.approx(s.amplitude)
    z = positions(obj.data)[:, 2].copy()
    obj.animation_data_clear()
    s.wind_speed = 20.0
    assert np.array_equal(positions(obj.data)[:, 2], z)


def test_choppy_and_travelling(sea, bridge):
    s = sea.projgrid
    s.wind_direction = 0.0
    # The sea the settings make: choppy, and its heights along the wind move downwind.
    source = bridge.scene.height_field(s)
    assert source.bounds(10.0)[1] > 0.05
    x = np.linspace(0.0, 400.0, 4001)
    a = source.heights(x, np.zeros_like(x), 10.0)
    b = source.heights(x, np.zeros_like(x), 11.0)
    lags = np.arange(-200, 201)
    corr = [np.dot(a[200:-200], b[200 + k:len(b) - 200 + k]) for k in lags]
    assert lags[int(np.argmax(corr))] * 0.1 > 2.0  # metres downwind in a second


def test_a_nan_wave_setting_is_named_and_nothing_drawn(sea, extension):
    """A wave setting Blender lets through but the sea cannot take (NaN: Python and drivers
    can set it) is named on the panel, and the ocean is empty until it is mended."""
    stats_lines = extension.panels.ocean_panel.stats_lines
    count = len(sea.data.vertices)
    for name in ("wind_speed", "wind_direction", "fetch", "swell_period"):
        good = getattr(sea.projgrid, name)
        setattr(sea.projgrid, name, float("nan"))
        assert stats_lines(sea, bpy.context.scene)[0] == (
            "ERROR", f"Not built: {name}: must be finite, got nan")
        assert len(sea.data.vertices) == 0
        setattr(sea.projgrid, name, good)
        assert len(sea.data.vertices) == count


def test_foam_covers_the_sea_at_a_strong_wind(sea, state):
    """At 14 m/s the foam attribute is not empty (it was, the noise's threshold taken from
    heights the mesh did not show), and foam is listed active. (Whitecaps cover 1.4 % of the
    sea then: a grid of this size has vertices enough near the camera to catch some.)"""
    sea.projgrid.resolution_x, sea.projgrid.resolution_y = 257, 257
    sea.projgrid.wind_speed = 14.0
    assert "FOAM" in sea.projgrid.active_effects
    foam = np.empty(len(sea.data.vertices), np.float32)
    sea.data.attributes["projgrid_foam"].data.foreach_get("value", foam)
    assert 0.0 < foam.mean() < 0.2


def test_playing_calibrates_the_coming_seconds_foam_ahead(sea, bridge, extension):
    """A viewport frame with whitecaps starts the next two seconds' calibrations on the worker
    (so playback does not stall each second); a render's frame does not (it has no next)."""
    foam = extension.projgrid_addon.foam
    sea.projgrid.foam = "ON"
    scene = bpy.context.scene
    bridge.ahead.finish()
    scene.frame_set(30)  # 1.25 s at 24 fps: the calibrations of 2 s and 3 s are ahead
    bridge.ahead.finish()
    source = bridge.scene.height_field(sea.projgrid)
    coverage = foam.active_coverage(source, sea.projgrid.wind_speed)
    assert all(foam.CALIBRATIONS.has(source, (t, coverage, 16384)) for t in (1.0, 2.0, 3.0))


def test_the_worker_waits_while_a_frame_is_built(sea, bridge, extension, monkeypatch):
    """The worker making calibrations ahead takes no cue while a frame is built (the threads
    share the interpreter: it would slow the frame as much as it works) and goes on when the
    frame ends, while the frame waits for a calibration it is making (no deadlock), and once
    the playback is within half a second of needing it."""
    foam, ahead = extension.projgrid_addon.foam, bridge.ahead
    sea.projgrid.foam = "ON"
    bpy.context.scene.frame_set(30)
    ahead.finish()
    source = bridge.scene.height_field(sea.projgrid)
    coverage = foam.active_coverage(source, sea.projgrid.wind_speed)
    for t in (30.0, 31.0):  # what a frame at 30 s makes itself
        foam.CALIBRATIONS.get(source, (t, coverage, 16384))
    cues, crest_cue = [], foam.crest_cue
    monkeypatch.setattr(foam, "crest_cue", lambda *a, **k: (cues.append(1), crest_cue(*a, **k))[1])
    safety = threading.Timer(30.0, ahead._IDLE.set)  # a deadlock fails the test, not CI
    safety.start()

    def until(seen, limit=10.0):
        start = time.perf_counter()
        while not seen() and time.perf_counter() - start < limit:
            time.sleep(0.005)
        return seen()
    with ahead.frame():  # second 32's, needed from 31 s: not yet
        assert ahead.calibrate(source, 30.0, sea.projgrid.wind_speed) == 1
        time.sleep(0.5)
        assert not cues and foam.CALIBRATIONS.making() == 1
    assert until(lambda: cues)  # the frame over, the worker begins
    start = time.perf_counter()
    with ahead.frame():
        assert foam.CALIBRATIONS.making() == 1  # begun, not made: waited for
        made = foam.CALIBRATIONS.get(source, (32.0, coverage, 16384))
    assert made is not None and time.perf_counter() - start < 20.0
    ahead.finish()
    cues.clear()
    with ahead.frame():  # at 40.2 s second 41's is needed now: made beside the frame
        assert ahead.calibrate(source, 40.2, sea.projgrid.wind_speed) == 2
        assert until(lambda: cues)
    ahead.finish()
    safety.cancel()
    assert foam.CALIBRATIONS.making() == 0


def test_the_noise_foam_at_a_strong_wind_is_not_empty():
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean("PERLIN")
    obj.projgrid.wind_speed = 14.0
    foam = np.empty(len(obj.data.vertices), np.float32)
    obj.data.attributes["projgrid_foam"].data.foreach_get("value", foam)
    assert foam.max() > 0.0


def test_time_stretching_drives_the_shader_as_the_geometry(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    add_ocean()
    scene.render.frame_map_old, scene.render.frame_map_new = 100, 50
    scene.frame_set(10)
    assert bridge.shot.scene_time(scene) == pytest.approx(20.0 / scene.render.fps)


def test_an_empty_as_the_camera_is_followed(state):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    empty = bpy.data.objects.new("Eye", None)
    empty.location = (0.0, 0.0, 8.0)
    empty.rotation_euler = (math.radians(80.0), 0.0, 0.0)
    scene.collection.objects.link(empty)
    scene.camera = empty
    bpy.context.view_layer.update()
    before = state(obj).camera[0].copy()
    empty.location.x += 5.0
    bpy.context.view_layer.update()
    assert not np.array_equal(state(obj).camera[0], before)


def test_deleting_an_instancer_raises_nothing_and_drops_its_stand_in(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    sea = bpy.data.collections.new("Sea")
    sea.objects.link(obj)
    scene.collection.objects.unlink(obj)
    for name, z in (("A", 0.0), ("B", -2.0)):
        e = bpy.data.objects.new(name, None)
        e.instance_type, e.instance_collection, e.location.z = "COLLECTION", sea, z
        scene.collection.objects.link(e)
    bpy.context.view_layer.update()
    assert len([o for o in scene.objects if o.get("projgrid_stand_in")]) == 2
    raised = []
    handlers = bpy.app.handlers.depsgraph_update_post
    i = handlers.index(bridge.handlers.depsgraph_update_post)

    def recording(*args):  # Blender prints a handler's exception and goes on: keep it
        try:
            bridge.handlers.depsgraph_update_post(*args)
        except Exception as e:
            raised.append(e)

    handlers[i] = recording
    try:
        bpy.data.objects.remove(bpy.data.objects["B"])
        bpy.context.view_layer.update()
    finally:
        handlers[handlers.index(recording)] = bridge.handlers.depsgraph_update_post
    assert raised == []
    assert len([o for o in scene.objects if o.get("projgrid_stand_in")]) == 1


def test_a_duplicate_gets_its_own_render_mesh(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = 32, 18
    obj.projgrid.render_resolution_x, obj.projgrid.render_resolution_y = 9, 17
    bpy.ops.render.render()
    twin = obj.copy()
    twin.data = obj.data.copy()
    twin.location.z = -3.0
    scene.collection.objects.link(twin)
    bpy.context.view_layer.update()
    drawn = {}

    def capture(scene, _=None):
        drawn.update({o.name: o.data for o in (obj, twin)})

    bpy.app.handlers.render_post.append(capture)
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.render_post.remove(capture)
    assert drawn[obj.name] != drawn[twin.name]


def test_a_file_saved_while_rendering_is_mended_at_load(bridge, tmp_path):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    render_mesh = bpy.data.meshes.new("Ocean Render")
    render_mesh["projgrid_ocean"] = True
    obj.projgrid.render_mesh = render_mesh
    obj.data = render_mesh  # as a save in the middle of a render would have left it
    path = str(tmp_path / "swapped.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Ocean"]
    assert obj.projgrid.render_mesh is None and obj.data.name == "Ocean Render"
