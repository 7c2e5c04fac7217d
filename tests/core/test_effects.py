"""Effect decisions from scene facts, whitecap coverage, foam, and the box-in-view test."""

from dataclasses import replace

import numpy as np
import pytest

from projgrid_addon import HeightField, effects, foam, look, optics, sea_states
from projgrid_addon.camera import Camera, look_at, perspective
from projgrid_addon.daylight import sky_light
from projgrid_addon.effects import SceneFacts, SceneObject, crossing_boxes, decide


def facts(**kw):
    base = {"camera_height": 10.0, "bound": 1.0, "reach": 1.0, "wind_speed": 0.0,
            "sun_elevation": None}
    return SceneFacts(**{**base, **kw})


def on(decisions):
    return {e for e, (active, _) in decisions.items() if active}


def test_bare_calm_ocean_without_sun_needs_nothing():
    d = decide({}, facts())
    assert on(d) == set()
    assert d["local_reflections"][1] == "sky only: nothing above the water is mirrored in view"


def test_a_sun_alone_calls_for_nothing():
    """The sun's glint is the water's own reflection of the lamp (shaders/water.py), not an
    effect."""
    assert on(decide({}, facts(sun_elevation=35.0))) == set()


def test_foam_follows_the_wind():
    assert effects.whitecap_coverage(0.0) == 0.0
    assert effects.whitecap_coverage(10.0) == pytest.approx(1.59e-5 * 10**2.55)
    assert effects.whitecap_coverage(7.0, 2.0) > effects.whitecap_coverage(7.0)
    assert not decide({}, facts(wind_speed=2.0))["foam"][0]
    foam, reason = decide({}, facts(wind_speed=12.0))["foam"]
    assert foam and reason.startswith("wind 12 m/s")


def test_modes_override_auto_and_bad_modes_name_the_effect():
    assert decide({"godrays": "OFF"}, facts(camera_height=-3.0, sun_elevation=30.0))[
        "godrays"] == (False, "switched off")
    assert decide({"foam": "ON"}, facts())["foam"] == (True, "switched on")
    with pytest.raises(ValueError, match="foam"):
        decide({"foam": "SOMETIMES"}, facts())


def test_objects_decide_by_their_place_against_the_water_and_the_view():
    boat = SceneObject("Boat", -0.5, 3.0, True, mirrored_in_view=True)
    rock = SceneObject("Rock", -8.0, -4.0, True)
    gull = SceneObject("Gull", 20.0, 21.0, False, mirrored_in_view=True)  # above the view
    hidden = SceneObject("Behind", -5.0, 5.0, False)
    d = decide({}, facts(objects=[hidden]))
    assert not any(d[e][0] for e in
                   ("contact_foam", "refraction", "caustics", "local_reflections"))
    d = decide({}, facts(objects=[boat, rock, gull], sun_elevation=40.0))
    assert on(d) == {"contact_foam", "refraction", "caustics", "local_reflections"}
    assert d["contact_foam"][1] == ("'Boat' crosses the surface in view, the waves' reach "
                                    "±1 m (5 σ of their height)")
    assert d["refraction"][1] == "'Boat', 'Rock' is below the surface in view"
    assert d["caustics"][1].startswith("sun 40° above the horizon, 'Boat', 'Rock'")
    assert d["local_reflections"][1] == "'Boat', 'Gull' stands above the water, mirrored in view"
    d = decide({}, facts(objects=[boat, rock, gull, hidden], sun_elevation=-3.0))
    assert not d["caustics"][0] and "below the horizon" in d["caustics"][1]


def test_a_floating_boat_gets_no_contact_foam_but_is_refracted_and_mirrored():
    """A float rises and falls with the waves, so none wash up it: no contact foam for it
    (its foam is its wake's), while the water still refracts and mirrors it."""
    afloat = SceneObject("Boat", -0.5, 3.0, True, mirrored_in_view=True, rides=True)
    d = decide({}, facts(objects=[afloat], sun_elevation=40.0))
    assert on(d) == {"refraction", "caustics", "local_reflections"}
    assert d["contact_foam"][1].startswith("nothing in view crosses the surface")
    assert not len(crossing_boxes(facts(objects=[replace(afloat, corners=np.zeros((8, 3)))])))


def test_underwater_camera():
    d = decide({}, facts(camera_height=-3.0, sun_elevation=30.0))
    assert on(d) == {"underwater", "godrays"}
    assert d["underwater"][1] == "camera 3 m below the surface"
    assert d["godrays"][1] == "camera 3 m below the surface, sun 30° above the horizon"
    assert not d["refraction"][0] and "below the surface" in d["refraction"][1]
    assert on(decide({}, facts(camera_height=-3.0))) == {"underwater"}  # no sun: no godrays


def test_local_reflections_need_a_mirror_image_in_view_and_nothing_in_front_of_it():
    mast = SceneObject("Mast", 0.0, 8.0, True, mirrored_in_view=True)
    assert not decide({}, facts(objects=[SceneObject("Mast", 0.0, 8.0, True)]))[
        "local_reflections"][0]  # seen, but its mirror image is not
    assert not decide({}, facts(objects=[mast], camera_height=-2.0))["local_reflections"][0]
    # Under a camera 3 m up, a floor 4 m down is below the capture point; one 2 m down stands
    # in front of the mirror image, unless its own mirror image is out of view.
    deep, shallow, aside = (SceneObject("Floor", -d - 1.0, -d, True, mirrored_in_view=m)
                            for d, m in ((4.0, True), (2.0, True), (2.0, False)))
    for floor in (deep, aside):
        d = decide({}, facts(objects=[mast, floor], camera_height=3.0))
        assert d["local_reflections"] == (True, "'Mast' stands above the water, mirrored in view")
    d = decide({}, facts(objects=[mast, shallow], camera_height=3.0))
    why = ("'Floor' would show in the reflection (under the water, shallower than the camera's "
           "3 m, in front of the mirror image)")
    assert d["local_reflections"] == (False, why)
    d = decide({"local_reflections": "ON"}, facts(objects=[mast, shallow], camera_height=3.0))
    assert d["local_reflections"] == (True, f"switched on, but {why}")


def test_the_mirror_capture_continues_every_reflected_ray():
    """Flat water: the ray from the eye to any surface point, reflected there, runs along the
    line from the capture point through that surface point."""
    eye, level = np.array([3.0, -2.0, 7.5]), 1.5
    location, half, clip = optics.mirror_capture(eye, level, 0.8, 500.0)
    assert location == (3.0, -2.0, -4.5) and clip == 6.0
    assert half == (500.0, 500.0, 6.8)  # the slab reaches the crests, level + bound
    rng = np.random.default_rng(2)
    points = np.column_stack([rng.uniform(-200, 200, (50, 2)), np.full(50, level)])
    incoming = points - eye
    reflected = incoming * (1.0, 1.0, -1.0)
    from_capture = points - np.array(location)
    cross = np.cross(reflected, from_capture)
    assert np.abs(cross).max() <= 1e-9 * np.abs(reflected).max() * np.abs(from_capture).max()
    assert (np.einsum("ij,ij->i", reflected, from_capture) > 0).all()  # same direction


def test_switched_on_effects_are_active():
    everything = dict.fromkeys(effects.EFFECTS, "ON")
    assert on(decide(everything, facts())) == set(effects.EFFECTS)


def test_boxes_in_view():
    cam = Camera(look_at((0, 0, 10), (0, 100, 0)), perspective(np.radians(50), 16 / 9, 0.1, 1e4))
    unit = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    boxes = np.stack([unit + (0, 50, 0), unit + (0, -50, 0), unit * 1000 + (-500, -500, -500)])
    assert effects.boxes_in_view(cam, boxes).tolist() == [True, False, True]


def test_whitecaps_cover_the_share_at_every_band_limit():
    """The foam a vertex gets is calibrated at its own band limit, so the mean foam over the
    sea is the coverage whatever detail the geometry holds; where it holds no wave, the
    share itself (the whitecaps of waves no vertex holds, as the shader shows far away)."""
    hf = HeightField(amplitude=1.0, octaves=6)
    calibration = foam.foam_thresholds(hf, 3.0, 0.02)
    x, y = np.random.default_rng(8).uniform(-5e3, 5e3, (2, 100_000))
    for lod in (1.0, 2.5, 4.0, 10.0):
        lods = np.full(x.shape, lod, np.float32)
        cover = foam.whitecaps(hf.foam_cue(np.stack([x, y]), 3.0, lods), lods, calibration)
        assert cover.dtype == np.float32 and 0.0 <= cover.min() and cover.max() <= 1.0
        assert cover.mean() == pytest.approx(0.02, rel=0.3), lod
    lods = np.zeros(x.shape, np.float32)  # no octave in the geometry
    assert foam.whitecaps(hf.foam_cue(np.stack([x, y]), 3.0, lods), lods,
                             calibration) == pytest.approx(np.full(x.shape, 0.02), rel=1e-3)
    calm = HeightField(amplitude=0.0, octaves=6)  # no wave at all: no foam
    calm_foam = foam.whitecaps(calm.foam_cue(np.stack([x, y]), 3.0, None), None,
                                  foam.foam_thresholds(calm, 3.0, 0.02))
    assert calm_foam.max() == 0.0
    again = foam.foam_thresholds(hf, 3.0, 0.02)
    assert all(np.array_equal(a, b) for a, b in zip(calibration, again, strict=True))


def unit_box(lo, hi):
    """Corners in Blender's bound_box order (x slowest, z fastest, y as 0 0 1 1)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return np.array([[x, y, z] for x in (x0, x1) for y, z in
                     ((y0, z0), (y0, z1), (y1, z1), (y1, z0))], float)


def test_contact_foam_rings_the_box_and_fades_with_distance():
    box = unit_box((-1, -1, -2), (1, 1, 2))
    x = np.array([0.0, 1.0, 1.25, 1.5, 3.0, -1.25])
    cover = foam.contact_foam(x, np.zeros_like(x), np.zeros_like(x), [box], 0.5)
    assert cover.dtype == np.float32
    assert cover.tolist() == pytest.approx([1.0, 1.0, 0.25, 0.0, 0.0, 0.25])
    # A box rotated 45° about z: a point 1.2 m out along its diagonal direction is within reach
    # of the rotated box's corner only (the distance is taken in the box's own frame).
    c, s_ = np.cos(np.pi / 4), np.sin(np.pi / 4)
    turned = box @ np.array([[c, s_, 0], [-s_, c, 0], [0, 0, 1]])
    point = np.array([np.sqrt(2) + 0.2]), np.zeros(1), np.zeros(1)
    assert foam.contact_foam(*point, [turned], 0.5)[0] == pytest.approx((1 - 0.4) ** 2)
    assert foam.contact_foam(*point, np.zeros((0, 8, 3)), 0.5)[0] == 0.0


def test_crossing_boxes_are_the_ones_in_view_that_cross_the_water():
    box = unit_box((-1, -1, -2), (1, 1, 2))
    boat = SceneObject("Boat", -2.0, 2.0, True, box)
    deep = SceneObject("Deep", -9.0, -5.0, True, box - (0, 0, 7))
    hidden = SceneObject("Hidden", -2.0, 2.0, False, box)
    boxes = effects.crossing_boxes(facts(objects=[boat, deep, hidden]))
    assert boxes.shape == (1, 8, 3) and np.array_equal(boxes[0], box)


def wavy_surface(n=257, span=40.0, amplitude=0.5, wavelength=5.0):
    x, y = np.meshgrid(np.linspace(0, span, n), np.linspace(0, span, n))
    return x, y, amplitude * np.sin(2 * np.pi * x / wavelength)


def test_caustics_are_one_on_flat_water_and_focus_under_crests():
    x, y, h = wavy_surface()
    sun = (0.0, 0.0, 1.0)
    flat = optics.caustic_intensity((x, y, np.zeros_like(x)), (0.3, 0.1, 0.8), 2.0)
    assert flat == pytest.approx(np.ones(x.size), abs=1e-6)
    wavy = optics.caustic_intensity((x, y, h), sun, 2.0).reshape(x.shape)
    inner = wavy[2:-2, 2:-2]
    # Crests are thin lenses of curvature k = A (2 pi / wavelength)^2 and focal length
    # f = n / ((n - 1) k): d below the crest the light is 1 / (1 - d / f) (paraxial), and d below
    # a trough 1 / (1 + d / f). The receiver is 2 m below the level: 2.5 m below crests.
    crest = np.isclose(np.sin(2 * np.pi * x / 5.0), 1.0, atol=1e-3)[2:-2, 2:-2]
    trough = np.isclose(np.sin(2 * np.pi * x / 5.0), -1.0, atol=1e-3)[2:-2, 2:-2]
    assert crest.any() and trough.any()
    f = 1.333 / (0.333 * 0.5 * (2 * np.pi / 5.0) ** 2)
    assert inner[crest] == pytest.approx(1 / (1 - 2.5 / f), rel=0.03)
    assert inner[trough] == pytest.approx(1 / (1 + 1.5 / f), rel=0.03)
    # Deeper receivers see the focus sharpen (up to the focal depth).
    deeper = optics.caustic_intensity((x, y, h), sun, 4.0).reshape(x.shape)[2:-2, 2:-2]
    assert deeper[crest].min() > inner[crest].min()
    assert not optics.caustic_intensity((x, y, h), (0.0, 0.3, -0.5), 2.0).any()  # sun set


def test_caustic_shadow_is_the_mean_on_flat_water_and_bounded():
    shadow = optics.caustic_shadow(np.array([0.0, 1.0, 2.0, 50.0]))
    assert shadow.tolist() == [0.0, optics.CAUSTIC_MEAN, 1.0, 1.0]


def test_receiving_depth_is_where_the_submerged_objects_are():
    assert optics.receiving_depth(facts()) == 2.0
    floor = SceneObject("Floor", -6.0, -6.0, True)
    rock = SceneObject("Rock", -3.0, -1.0, True)
    pier = SceneObject("Pier", -4.0, 5.0, True)
    far = SceneObject("Far", -40.0, -30.0, False)
    assert optics.receiving_depth(facts(objects=[floor, rock, pier, far])) == 2.0
    assert optics.receiving_depth(facts(objects=[floor])) == 6.0


def test_the_godrays_look_the_caustic_tile_up_along_the_refracted_sun():
    sun = np.array([0.3, -0.2, 0.6])
    d = optics.refracted_sun(sun)
    assert np.linalg.norm(d) == pytest.approx(1.0) and d[2] < 0
    sin_in = np.linalg.norm(np.cross(sun / np.linalg.norm(sun), (0, 0, 1)))
    assert np.linalg.norm(np.cross(d, (0, 0, 1))) == pytest.approx(sin_in / 1.333)  # Snell
    level, corner, size = 0.5, (10.0, -20.0), 64.0
    a, b, c = optics.tile_lookup(sun, level, corner, size)
    entry = np.array([30.0, 5.0, level])  # where the sun ray enters the water
    for s in (0.0, 3.0, 12.0):
        q = entry + s * d  # further down the same ray
        uv = (a @ q + c[0], b @ q + c[1])
        assert uv == pytest.approx(((30.0 - 10.0) / 64.0, (5.0 + 20.0) / 64.0))


def test_the_caustic_tile_is_the_caustics_on_a_regular_grid():
    hf = HeightField(amplitude=0.4, octaves=4, wave_scale=10.0)
    tile = optics.caustic_tile(hf, 2.0, (5.0, 7.0), 32.0, 64, (0.2, 0.1, 0.9), 3.0)
    assert tile.shape == (64, 64) and tile.dtype == np.float32
    assert tile.mean() == pytest.approx(1.0, abs=0.1) and tile.std() > 0.05
    flat = optics.caustic_tile(HeightField(amplitude=0.0), 2.0, (5.0, 7.0), 32.0, 16,
                                (0.2, 0.1, 0.9), 3.0)
    assert np.allclose(flat, 1.0, atol=1e-5)


def test_facts_keys_differ_exactly_when_the_facts_do():
    box = unit_box((-1, -1, -2), (1, 1, 2))
    base = facts(objects=[SceneObject("Boat", -2.0, 2.0, True, box)])
    same = facts(objects=[SceneObject("Boat", -2.0, 2.0, True, box.copy())])
    assert base.key() == same.key()
    moved = facts(objects=[SceneObject("Boat", -2.0, 2.0, True, box + (0.0, 1e-6, 0.0))])
    mirrored = facts(objects=[SceneObject("Boat", -2.0, 2.0, True, box, True)])
    for other in (moved, mirrored, facts(), facts(camera_height=9.0), facts(sun_elevation=3.0)):
        assert other.key() != base.key()


def test_the_body_s_light_is_the_daylight_s_share():
    """optics.body_light: 1 in the daylight the Water Colour is given in (Add Ocean's sun and
    clear sky), nought in the dark, the sun's and the sky's parts apart, per channel."""
    daylight = np.array(look.DAYLIGHT)
    clear = optics.sky_irradiance(1.0, 0.0)
    sun = daylight - np.array(sky_light(look.SUN_ELEVATION))
    assert clear == pytest.approx(daylight - sun)
    assert optics.body_light(sun, clear) == pytest.approx((1.0, 1.0, 1.0))
    assert optics.body_light(0.0, optics.sky_irradiance(0.0, 0.3)) == (0.0, 0.0, 0.0)
    # the sky follows the sun: redder and dimmer at sunset
    low, high = optics.sky_irradiance(1.0, 0.0, 3.0), optics.sky_irradiance(1.0, 0.0, 45.0)
    assert low[0] / low[2] > high[0] / high[2] and low[1] < 0.5 * high[1]
    assert optics.body_light(0.0, clear) == pytest.approx((daylight - sun) / daylight)
    assert optics.body_light((1.2, 0.6, 0.0), 0.5 * clear) == pytest.approx(
        (np.array((1.2, 0.6, 0.0)) + 0.5 * (daylight - sun)) / daylight)


def test_the_overcast_lights_the_sea_as_the_cie_sky():
    """Under the overcast (Sea State's storm sky) the sky's irradiance on the sea is the CIE
    standard overcast sky's, radiance Z (1 + 2 sin h) / 3, integrated here over the hemisphere
    (weighed by sin h), grey as its zenith: not the clear sky's blue; between, in proportion."""
    n = 2000
    h = (np.arange(n) + 0.5) / n * np.pi / 2.0
    weight = 2.0 * np.pi * np.sin(h) * np.cos(h) * (np.pi / 2.0 / n)
    zenith = np.array(look.OVERCAST_ZENITH)
    want = zenith * ((1.0 + 2.0 * np.sin(h)) / 3.0 * weight).sum()
    assert optics.sky_irradiance(1.0, 1.0) == pytest.approx(want, rel=1e-5)
    assert optics.sky_irradiance(0.5, 1.0) == pytest.approx(0.5 * want, rel=1e-5)
    half = optics.sky_irradiance(1.0, 0.5)
    assert half == pytest.approx(0.5 * (want + optics.sky_irradiance(1.0, 0.0)))
    blue = optics.body_light(0.0, optics.sky_irradiance(1.0, 0.0))
    grey = optics.body_light(0.0, optics.sky_irradiance(1.0, 1.0))
    assert blue[2] / blue[0] > 1.2 * grey[2] / grey[0]  # the clear sky's light is bluer


def test_the_sky_clouds_over_with_the_wind_without_a_step():
    """Sea State's overcast: none to a fresh breeze's wind, all from a gale's, and between them
    continuous in the wind (a sky keyed to a rising wind closes gradually; stepped by the
    integer force it jumped by a third between forces 5 and 7), the presets' at their winds."""
    winds = np.linspace(0.0, 30.0, 3001)
    cloud = np.array([sea_states.overcast_for_wind(u) for u in winds])
    assert cloud[winds <= 9.4].max() == 0.0 and cloud[winds >= 19.0].min() == 1.0
    assert (np.diff(cloud) >= 0.0).all() and np.diff(cloud).max() < 0.002
    for force, (_, wind, *_) in sea_states.BEAUFORT.items():
        assert sea_states.overcast(force) == sea_states.overcast_for_wind(wind)
    assert 0.0 < sea_states.overcast(6) < sea_states.overcast(7) < 1.0
    with pytest.raises(ValueError, match="wind_speed"):
        sea_states.overcast_for_wind(float("nan"))
