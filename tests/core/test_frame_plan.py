"""The plan of a frame (projgrid_addon/frame_plan.py) runs on plain inputs without Blender:
the grid, the effects on and their fields, the shader's values, the gusts' drift."""

from dataclasses import replace

import numpy as np
import pytest

from projgrid_addon import HeightField, daylight, effects, frame_plan, past_grid, shading
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.look import FOAM_COLOUR, WATER_COLOUR
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState, integrate

SEA = dict(resolution_x=65, resolution_y=129, render_resolution_x=65, render_resolution_y=129,
           noise_from_wind=True, amplitude=0.5, wave_scale=40.0, octaves=8, roughness=0.5,
           speed=1.0, seed=0, projector_elevation=0.0, noise="FAST", wind_speed=12.0,
           height_source="SPECTRUM", spectrum="JONSWAP", wind_direction=0.5, fetch=0.0,
           choppiness=1.0, swell_height=0.0, swell_direction=0.0, swell_period=10.0,
           **dict.fromkeys(effects.EFFECTS, "AUTO"), water_colour=WATER_COLOUR,
           foam_colour=FOAM_COLOUR, clarity=10.0, gusts=1.0)


def inputs(samples=None, frame=48.0, **settings):
    s = frame_plan.Settings(**{**SEA, **settings})
    view = look_at((0.0, 0.0, 6.0), (0.0, 100.0, 2.0))
    proj = perspective(np.radians(50.0), 16 / 9, 0.1, 1e4)
    facts = effects.SceneFacts(camera_height=6.0, bound=0.0, wind_speed=s.wind_speed,
                               sun_elevation=20.0, sun_direction=(0.0, 0.94, 0.34))
    return frame_plan.FrameInputs(
        settings=s, render=False, resolution=(65, 129), camera=(view, proj), world=np.eye(4),
        to_local=np.eye(3), time=frame / 24.0, frame=frame, per_frame=1.0 / 24.0,
        render_width=960, facts=facts, sun_light=(1.0, 1.0, 1.0), sky_strength=1.0,
        sky_overcast=0.0, sky_model="MULTIPLE_SCATTERING", sky_hazes=True,
        wind_samples=samples, vertices=0,
        our_material=True, volume_reach=100.0, ahead=False)


def test_a_plan_is_a_pure_function_of_its_inputs():
    a, b = frame_plan.plan(inputs()), frame_plan.plan(inputs())
    assert a.result.visible and np.array_equal(a.result.positions, b.result.positions)
    assert np.array_equal(a.whitecaps, b.whitecaps) and a.decisions == b.decisions
    assert a.layer is not None and a.warning is None


def test_effects_off_plan_no_fields():
    """Foam at a gale is whitecaps and their residual foam per vertex and the sea's shares
    for the shader, active and residual making Monahan's; off, neither (and no slope layer
    for a material that is not ours)."""
    on = frame_plan.plan(inputs(foam="ON"))
    assert on.on["foam"] and on.whitecaps.max() > 0.0 and on.residual.max() > 0.0
    active, residual, aged, _, blown = on.foam_look
    assert blown == 0.0  # 12 m/s: below Beaufort 7, no blown streaks
    assert 0.0 < aged < active < residual
    assert active + residual + aged == pytest.approx(effects.whitecap_coverage(12.0))
    off = frame_plan.plan(inputs(**dict.fromkeys(effects.EFFECTS, "OFF")))
    assert not any(off.on.values()) and off.foam_look is None
    assert off.caustics is None and off.residual is None
    assert off.godrays is None
    assert frame_plan.plan(replace(inputs(), our_material=False)).layer is None


def test_the_gusts_drift_by_the_wind_s_run():
    """A steady wind drifts the gusts at its velocity (no offset); a keyframed one by its run
    since frame 0: the driver, offset + frame x rate, reads the integral of its velocity."""
    steady = frame_plan.plan(inputs()).drift
    u, d = SEA["wind_speed"], SEA["wind_direction"]
    assert np.allclose(steady, [(u * np.cos(d) / 24.0, 0.0), (u * np.sin(d) / 24.0, 0.0),
                                (u / 24.0, 0.0)])
    frames = np.append(np.arange(0.0, 48.0), 48.0)
    speeds = 4.0 + 8.0 * frames / 48.0  # 4 -> 12 m/s, turning a quarter
    directions = d + (np.pi / 2.0) * frames / 48.0
    drift = frame_plan.gust_drift(frame_plan.Settings(**SEA), 1.0 / 24.0, 48.0,
                                  (frames, speeds, directions))
    run = shading.wind_run(frames / 24.0, speeds, directions)
    for (rate, offset), want in zip(drift, run, strict=True):
        assert offset + 48.0 * rate == pytest.approx(want)
    x = integrate(speeds * np.cos(directions), frames / 24.0)
    assert run[0] == pytest.approx(x, rel=1e-3)


def test_auto_decides_by_the_reach_of_the_sea_in_a_shot():
    """A rock whose top is 2 m under a Beaufort 4 sea (Hs about 1 m) crosses no surface: AUTO
    takes the sea to reach 5 standard deviations of its heights (1.3 m), not its bound (the sum
    of every band's extreme, 3 m here), and says so; 0.5 m under, it crosses."""
    force_4 = dict(wind_speed=6.7, fetch=0.0, choppiness=0.8, foam="OFF")
    for top, crossing in ((-2.0, False), (-0.5, True)):
        rock = effects.SceneObject("Rock", -6.0, top, True, corners=np.zeros((8, 3)))
        planned = replace(inputs(**force_4), facts=replace(inputs().facts, objects=[rock]))
        plan = frame_plan.plan(planned)
        on, reason = plan.decisions["contact_foam"]
        assert on == crossing and "5 σ" in reason
        assert plan.bound > 2.0  # the bound alone would have counted the rock as crossing


SOURCES = {"SPECTRUM": lambda: SpectralField(SeaState(wind_speed=12.0), choppiness=1.0, seed=2),
           "PERLIN": lambda: HeightField(amplitude=1.0, choppiness=0.6, seed=2)}


@pytest.mark.parametrize("source", SOURCES)
def test_time_is_an_argument_of_every_read(source):
    """A height source answers for the time it is asked (no state to set up first): its bounds
    and fields at a time are the same, bit for bit, whatever times were read before, and a
    plan of frame 48 is the same after plans of other frames (a farm renders frames alone and
    out of order)."""
    xy = np.stack(np.meshgrid(np.linspace(-50.0, 50.0, 9), np.linspace(0.0, 400.0, 17)))

    def read(hf, t):
        h, side = hf.displacement(xy, t)
        return hf.bounds(t), h, side

    want = read(SOURCES[source](), 7.0)
    hf = SOURCES[source]()
    for t in (3.0, 7.0, 11.5, 3.0):
        read(hf, t)
        got = read(hf, 7.0)
        assert got[0] == want[0] and got[0][1] > 0.0
        assert np.array_equal(got[1], want[1]) and np.array_equal(got[2], want[2])
    assert not hasattr(hf, "prepare")
    first = frame_plan.plan(inputs(height_source=source, frame=48.0))
    frame_plan.plan(inputs(height_source=source, frame=12.0))
    again = frame_plan.plan(inputs(height_source=source, frame=48.0))
    assert again.bound == first.bound
    assert np.array_equal(again.result.positions, first.result.positions)


def test_a_dolly_s_plan_reads_the_residual_s_past_on_canonical_grids(monkeypatch):
    """FrameInputs.dolly reaches the residual foam: a dollying camera's plan takes its past on
    canonical cameras' grids (past_grid.py), under a keyed wind too (its grid's volume is the
    span's, the same at every frame), any other camera's on its own grid."""
    asked, canonical = [], past_grid._canonical
    monkeypatch.setattr(past_grid, "_canonical", lambda *a: asked.append(1) or canonical(*a))
    for dolly, keyed in ((False, None), (True, None), (True, (11.0, 13.0))):
        asked.clear()
        plan = frame_plan.plan(replace(inputs(foam="ON", wind_span=keyed), dolly=dolly))
        assert plan.residual.max() > 0.0 and bool(asked) == dolly


def test_the_water_hazes_into_our_sky_only():
    """The air's extinction the plan gives the water: Koschmieder's for the wind's visibility
    under our sky (daylight.haze_extinction), none under another world, whose light the water
    does not know."""
    ours = frame_plan.plan(inputs(wind_speed=26.5))
    assert ours.haze == pytest.approx(daylight.KOSCHMIEDER / daylight.SPRAY_VISIBILITY)
    theirs = frame_plan.plan(replace(inputs(wind_speed=26.5), sky_hazes=False))
    assert theirs.haze == 0.0
