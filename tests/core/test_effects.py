"""Effect decisions from scene facts, whitecap coverage, foam, and the box-in-view test."""

import numpy as np
import pytest

from projgrid_addon import HeightField, effects
from projgrid_addon.camera import Camera, look_at, perspective
from projgrid_addon.effects import SceneFacts, SceneObject, decide


def facts(**kw):
    base = {"camera_height": 10.0, "bound": 1.0, "wind_speed": 0.0, "sun_elevation": None}
    return SceneFacts(**{**base, **kw})


def on(decisions):
    return {e for e, (active, _) in decisions.items() if active}


def test_bare_calm_ocean_without_sun_needs_nothing():
    d = decide({}, facts())
    assert on(d) == set()
    assert d["local_reflections"][1] == "sky only: nothing stands above the water in view"
    assert d["sun_glint"][1] == "no sun lamp"


def test_sun_above_the_horizon_turns_on_glint_and_below_it_does_not():
    assert on(decide({}, facts(sun_elevation=35.0))) == {"sun_glint"}
    d = decide({}, facts(sun_elevation=-5.0))
    assert not d["sun_glint"][0] and "below the horizon" in d["sun_glint"][1]


def test_foam_follows_the_wind():
    assert effects.whitecap_coverage(0.0) == 0.0
    assert effects.whitecap_coverage(10.0) == pytest.approx(1.59e-5 * 10**2.55)
    assert effects.whitecap_coverage(7.0, 2.0) > effects.whitecap_coverage(7.0)
    assert not decide({}, facts(wind_speed=2.0))["foam"][0]
    foam, reason = decide({}, facts(wind_speed=12.0))["foam"]
    assert foam and reason.startswith("wind 12 m/s")


def test_modes_override_auto_and_bad_modes_name_the_effect():
    assert decide({"sun_glint": "OFF"}, facts(sun_elevation=30.0))["sun_glint"] == (
        False, "switched off")
    assert decide({"foam": "ON"}, facts())["foam"] == (True, "switched on")
    with pytest.raises(ValueError, match="foam"):
        decide({"foam": "SOMETIMES"}, facts())


def test_objects_decide_by_their_place_against_the_water_and_the_view():
    boat = SceneObject("Boat", -0.5, 3.0, True)
    rock = SceneObject("Rock", -8.0, -4.0, True)
    gull = SceneObject("Gull", 20.0, 21.0, True)
    hidden = SceneObject("Behind", -5.0, 5.0, False)
    d = decide({}, facts(objects=[hidden]))
    assert not any(d[e][0] or "needed" in d[e][1] for e in
                   ("contact_foam", "refraction", "caustics", "local_reflections"))
    d = decide({}, facts(objects=[boat, rock, gull], sun_elevation=40.0))
    assert "'Boat'" in d["contact_foam"][1] and "needed" in d["contact_foam"][1]
    assert "'Boat', 'Rock'" in d["refraction"][1]
    assert "needed" in d["caustics"][1] and "sun 40°" in d["caustics"][1]
    assert "'Boat', 'Gull'" in d["local_reflections"][1]


def test_underwater_camera():
    d = decide({}, facts(camera_height=-3.0, sun_elevation=30.0))
    assert d["underwater"][1].startswith("needed (camera 3 m below the surface")
    assert "needed" in d["godrays"][1]
    assert not d["refraction"][0] and "below the surface" in d["refraction"][1]


def test_unrendered_effects_are_never_active():
    everything = dict.fromkeys(effects.EFFECTS, "ON")
    assert on(decide(everything, facts())) == set(effects.RENDERED)


def test_boxes_in_view():
    cam = Camera(look_at((0, 0, 10), (0, 100, 0)), perspective(np.radians(50), 16 / 9, 0.1, 1e4))
    unit = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    boxes = np.stack([unit + (0, 50, 0), unit + (0, -50, 0), unit * 1000 + (-500, -500, -500)])
    assert effects.boxes_in_view(cam, boxes).tolist() == [True, False, True]


def test_foam_threshold_matches_the_coverage_and_foam_is_deterministic():
    hf = HeightField(amplitude=1.0, octaves=6)
    t = effects.foam_threshold(hf, 3.0, 0.02)
    x, y = np.random.default_rng(8).uniform(-5e3, 5e3, (2, 100_000))
    h = hf.heights(x, y, 3.0)
    assert np.mean(h > t) == pytest.approx(0.02, abs=0.01)
    assert effects.foam_threshold(hf, 3.0, 0.02) == t
    foam = effects.foam_amount(h, t, 0.1)
    assert foam.dtype == np.float32 and foam.min() == 0.0 and foam.max() == 1.0
    assert np.array_equal(foam > 0, h > t)
