"""The foam against Monahan's whitecap share: the fold cue a mesh shows, the calibration over
time and band limit, the shader's grain and the far sea's share."""

import threading
import types

import numpy as np
import pytest
from look_numpy import NUMPY, footprint_log, grain_facs, group_inputs

from projgrid_addon import (
    HeightField,
    band_limit,
    effects,
    foam,
    residual_foam,
    sea_states,
    shading,
    water_model,
)
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.look import FOAM_GRAIN, FOAM_LACE, FOAM_STREAK, WHITECAP
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

from .spectral_checks import assert_spreads_alike


def test_choppy_points_move_toward_the_crests():
    """Tessendorf's displacement sharpens the crests: the surface compresses (Jacobian < 1)
    where it is high, and stretches where it is low."""
    source = SpectralField(SeaState(wind_speed=12.0), choppiness=1.0, seed=1)
    x, y = np.random.default_rng(2).uniform(0.0, 2000.0, (2, 40_000))
    xy = np.stack([x, y])
    h = source.heights(x, y, 3.0)
    j = source.jacobian(xy, 3.0)
    assert np.corrcoef(h, j)[0, 1] < -0.3
    assert j.mean() == pytest.approx(1.0, abs=0.05)  # as much stretched as compressed


def test_the_foam_calibration_sees_the_folding_as_a_mesh_does():
    """The Jacobian the whitecaps are calibrated on (differences over the vertex spacing a
    band limit stands for) is the one a mesh of that spacing shows between its vertices."""
    source = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=2)
    spacing = 1.5
    lod = band_limit.lod_for_spacing(source.wave_scale, spacing)
    k = np.arange(64) * spacing
    xy = np.stack(np.meshgrid(k, k + 300.0))
    lods = np.full(xy.shape[1:], lod, np.float32)
    h, d = source.displacement(xy, 5.0, lods)
    mesh = source.jacobian(xy, 5.0, lods, grid=xy + d)
    apart = source.jacobian(xy, 5.0, lods)
    assert np.abs(mesh - apart)[1:-1, 1:-1].max() < 1e-4
    assert mesh.std() > 0.02  # the sea folds and stretches: not a flat comparison


@pytest.mark.parametrize("u", [6.0, 10.0, 15.0, 20.0, 25.0])
def test_foam_covers_the_whitecap_share_and_stays_steady(u):
    """The mean foam over the sea is Monahan's whitecap coverage (check_whitecap_share_and_
    steadiness), at full detail, with a band whole and with a band fading in (most vertices
    hold one in part), and changes by less than 30 % in a second (the median over three seas,
    five below 10 m/s). One sea's change is itself uncertain: the calibration's 16384 points
    hold some 80 folds at 10 m/s, fewer below; over seeds 4-23 at 6 m/s it had a median of
    14 %, a 90th percentile of 26-31 % and reached 36-56 %."""
    sources = [SpectralField(SeaState(wind_speed=u), choppiness=0.8, seed=seed)
               for seed in range(7, 12 if u < 10.0 else 10)]
    fading = sorted(set(sources[0].levels))[len(set(sources[0].levels)) // 2]  # fades in to + 1
    check_whitecap_share_and_steadiness(sources, u, (fading + 1.0, fading + 0.6))


FOAM_POINTS = np.random.default_rng(3).uniform(-3e3, 3e3, (2, 60_000))


def check_whitecap_share_and_steadiness(sources, u, levels):
    """The mean foam of each of `sources` over FOAM_POINTS, at full detail and at each band
    limit of `levels`, at 10 s and 11 s, is Monahan's coverage for the wind `u` within the
    issue's factor of 2 (one sea's share is a sample: at 6 m/s seeds 4-13 gave 0.63-1.21 of
    it), their median within a factor of 1.5, and each changes by less than 30 % from the
    one time to the other (the median over the sources)."""
    want = effects.whitecap_coverage(u)
    lods = (None, *(np.full(FOAM_POINTS.shape[1:], level) for level in levels))
    shares, changes = [], []
    for source in sources:
        means = []
        for t in (10.0, 11.0):
            calibration = foam.foam_thresholds(source, t, want)
            for lod in lods:
                cover = foam.whitecaps(foam.crest_cue(source, FOAM_POINTS, t, lod), lod,
                                       calibration)
                means.append(cover.mean())
        shares.append(np.divide(means, want))
        changes.append(np.abs(np.divide(means[len(lods):], means[:len(lods)]) - 1.0))
    assert ((0.5 < np.min(shares, axis=0)) & (np.max(shares, axis=0) < 2.0)).all(), shares
    assert ((1 / 1.5 < np.median(shares, axis=0)) & (np.median(shares, axis=0) < 1.5)).all(), (
        shares)
    assert (np.median(changes, axis=0) < 0.3).all(), changes


@pytest.mark.parametrize("u", [6.0, 15.0, 25.0])
def test_the_noise_s_foam_covers_the_whitecap_share_and_stays_steady(u):
    """The noise From Wind, choppy: its mean foam over the sea is Monahan's coverage within a
    factor of 1.5, at full detail and with an octave fading in, and changes by less than 30 %
    in a second. One sea: at 6 m/s the calibration's 16384 points hold some 25 foamed ones,
    so over seeds 0-4 and four times the cover ranged 0.65-1.18 times the share (seed 4's
    first second the low one)."""
    amplitude, wave_scale = sea_states.noise_waves(u)
    source = HeightField(amplitude=amplitude, wave_scale=wave_scale, choppiness=0.8, seed=0)
    check_whitecap_share_and_steadiness([source], u, (3.6,))


def test_a_swell_brings_no_foam_to_the_far_sea():
    """Seen from 30 m up, a 2.5 m swell crossing a gentle breeze's sea: the foam a frame's grid
    draws in the far field (its vertices holding no wave shorter than 16 m) covers Monahan's
    share within a factor of 3, in each octave of detail (the swell's core, kept there by the
    band limit along its headings, is not displaced sideways: it does not fold, and a ring of
    foam on its crests covered 20 to 50 times the share when it was)."""
    state = SeaState(wind_speed=4.4, wind_direction=np.pi / 2, swell_height=2.5,
                     swell_period=13.0, swell_direction=np.radians(10.0))
    source = SpectralField(state, choppiness=0.5, seed=0)
    eye = np.array([0.0, 0.0, 30.0])
    cam = (look_at(eye, eye + (0.0, 1.0, np.tan(np.radians(-6.0)))),
           perspective(np.radians(40.0), 16 / 9, 0.1, 1e5))
    result = build_grid(cam, source, time=2.0, resolution=(257, 513))
    want = effects.whitecap_coverage(4.4)
    xy, lod = result.base, result.lod.reshape(result.base.shape[1:])
    cover = foam.whitecaps(source.foam_cue(xy, 2.0, lod, grid=result.surface[:2]), lod,
                             foam.foam_thresholds(source, 2.0, want))
    for level in (-4.0, -5.0, -6.0, -7.0):
        near = np.abs(lod.ravel() - level) <= 0.5
        assert near.sum() > 1000 and want / 3.0 < cover[near].mean() < 3.0 * want, level


def test_a_gale_s_far_sea_is_as_white_as_its_whitecaps_cover():
    """Seen from 4 m up at a gale, the vertices far enough to hold no band of waves at all
    (beyond some 400 m) still stand for a sea whitecaps cover Monahan's share of: their foam,
    active, residual and aged together, is that share within 10 % (a threshold for 'no wave'
    there left it white-free, 1 % of the share)."""
    preset = sea_states.sea_state(8, np.pi / 2)
    state = SeaState(wind_speed=preset.wind_speed, wind_direction=np.pi / 2,
                     fetch=preset.fetch, swell_height=preset.swell_height,
                     swell_period=preset.swell_period,
                     swell_direction=sea_states.swell_direction(np.pi / 2))
    source = SpectralField(state, choppiness=preset.choppiness, seed=0)
    eye = np.array([0.0, 0.0, 4.0])
    cam = (look_at(eye, eye + (0.0, 1.0, np.tan(np.radians(-4.0)))),
           perspective(np.radians(40.0), 16 / 9, 0.1, 1e5))
    result = build_grid(cam, source, time=5.0, resolution=(129, 257),
                        crest=foam.whitecap_level(source))
    want = effects.whitecap_coverage(preset.wind_speed)
    active, residual = foam.foam_field(source, result, 5.0, preset.wind_speed, True, [], 0.0)
    cover = active + (1.0 - active) * residual
    cover += (1.0 - cover) * foam.foam_look(source, preset.wind_speed)[2]
    bare = result.lod < source.first_level
    assert bare.sum() > 100
    assert cover[bare] == pytest.approx(want, rel=0.1)


def test_calibrations_are_kept_per_source_and_window_and_made_once():
    """What foam_thresholds calibrates is kept (foam.Calibrations) per source and window: the
    windows a playing sequence needs next are reserved once, one being made elsewhere (on the
    source's twin, as the Blender layer's worker does) is waited for, not made again, and it
    is bit for bit what the frame would make itself."""
    source = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=6)
    kept = foam.Calibrations()
    coverage = foam.foam_coverage(12.0)
    foam.foam_thresholds(source, 10.3, coverage, kept=kept)
    keys = foam.ahead(10.3, coverage)
    assert [k[0] for k in keys] == [11.0, 12.0] and kept.has(source, keys[0])
    assert kept.reserve(source, keys) == [keys[1]] and kept.reserve(source, keys) == []
    made, began = [], threading.Event()

    def worker():
        assert kept.start(source, keys[1])
        began.set()
        made.append(foam.calibration(source.twin(), *keys[1]))
        kept.put(source, keys[1], made[0])
        kept.release(source, keys[1])

    thread = threading.Thread(target=worker)
    thread.start()
    began.wait()
    got = kept.get(source, keys[1])  # waits for the worker's
    thread.join()
    assert got is made[0] and kept.making() == 0
    fresh = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=6)
    want = foam.calibration(fresh, *keys[1])
    assert all(np.array_equal(a, b) for a, b in zip(got, want, strict=True))
    # reserved but not started: the frame makes it (no wait for a worker's queue), the worker
    # skips it; a worker's calibration pauses before each level (where a frame holds it)
    later = foam.ahead(12.3, coverage)[1]
    assert kept.reserve(source, [later]) == [later]
    paused, worker_starts = [], []
    taken = kept.made(source, later, lambda: (worker_starts.append(kept.start(source, later)),
                                              foam.calibration(source.twin(), *later))[1])
    assert worker_starts == [False] and kept.making() == 0 and kept.has(source, later)
    again = foam.calibration(source.twin(), *later, pause=lambda: paused.append(1))
    assert len(paused) == len(source.foam_levels())
    assert all(np.array_equal(a, b) for a, b in zip(taken, again, strict=True))


@pytest.mark.parametrize("share", [0.002, 0.01, 0.05, 0.3, 0.7, 0.95, 1.0])
def test_the_grain_covers_a_vertex_s_share(share):
    """The shader's whitecaps (water_model.grain_cover, the node tree's formula) cover a
    vertex's share of a grain noise of the fitted CDF: their mean is the share, and nothing is
    drawn where the share is nought."""
    rank = water_model.grain_rank(NUMPY, grain_facs(2_000_000, 5))
    assert water_model.grain_cover(NUMPY, rank, share).mean() == pytest.approx(share, rel=0.05)
    assert water_model.grain_cover(NUMPY, rank, 0.0).max() == 0.0


def test_far_whitecaps_stay_specks():
    """From 4 m up, 400 m away a pixel is longer than the grain's and the lace's patches (2.7 m
    and 4 m: the water group's) along the view but its area holds few: the foam drawn there,
    active or residual, is specks of whole foam covering the share (water_model.foam_cover),
    not the share spread as a veil; at the horizon, where a pixel is longer than a whitecap
    (8 m), the sea's mean shares, the residual over what the active leaves."""
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    f = shading.filtering(proj, 960, SpectralField(SeaState(wind_speed=15.0)).slopes, 15.0)
    patches = 1.0 / (FOAM_GRAIN * np.sqrt(FOAM_STREAK)), 1.0 / FOAM_LACE
    assert patches == pytest.approx((2.72, 4.0), rel=0.01) and WHITECAP == 8.0
    fac, net = grain_facs(400_000, 3), grain_facs(400_000, 4)
    i = group_inputs(f, **{"Foam Coverage": 0.006, "Residual Coverage": 0.014})

    def drawn(d, active, residual):
        lp, log_cos = water_model.footprint(NUMPY, i, d, 4.0 / d)
        return water_model.foam_cover(NUMPY, i, active, residual, fac, fac[::-1], net, fac,
                                      fac, net, lp, log_cos)[0]
    assert np.exp(footprint_log(f, 400.0, 4.0 / 400.0)) > max(patches)
    for active, residual in ((0.05, 0.0), (0.0, 0.05)):
        near = drawn(400.0, active, residual)
        assert near.mean() == pytest.approx(0.05, rel=0.05)
        assert (near > 0.9).mean() > 0.5 * 0.05 and near.max() == 1.0
    far = drawn(5000.0, 0.3, 0.3)
    assert far == pytest.approx(0.006 + 0.994 * 0.014)


def test_a_frame_s_foam_and_bounds_do_not_hang_on_earlier_frames():
    """The foam calibrations prepare the sea at their own times; a frame's foam (with contact
    foam, whose reach is the waves' bound) and bound are the same computed alone or after an
    earlier frame of the same second."""
    state = SeaState(wind_speed=14.0)
    eye = np.array([0.0, 0.0, 10.0])
    cam = (look_at(eye, eye + (0.0, np.cos(0.35), -np.sin(0.35))),
           perspective(np.radians(40.0), 16 / 9, 0.1, 1e4))
    unit = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    boxes = (unit + (0.0, 30.0, 0.0))[None]

    def frame(source, t):
        result = build_grid(cam, source, time=t, resolution=(33, 65),
                            crest=foam.whitecap_level(source))
        return foam.foam_field(source, result, t, 14.0, True, boxes, 0.0), source.bounds(t)[0]

    cover, bound = frame(SpectralField(state, choppiness=1.0, seed=3), 12.5)
    source = SpectralField(state, choppiness=1.0, seed=3)
    frame(source, 12.45)
    again, bound_again = frame(source, 12.5)
    assert bound_again == bound
    assert all(np.array_equal(a, b) for a, b in zip(again, cover, strict=True))
    assert cover[0].max() > 0.0 and cover[1].max() > 0.0  # foamed: not nothing compared


def test_a_frame_s_folding_spreads_as_the_calibration_s():
    """On a real frame's grid (rows and columns of different spacings, turned to the view, far
    rows summed on every other point) the fold cue the vertices show spreads as the
    calibration's at the same band limits, of all its waves and of its crest sum's (the
    waves up to the whitecaps' level, which the frame's foam is drawn from; band_sum.py): the
    whitecaps cover the calibrated share on the mesh too."""
    source = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=4)
    eye = np.array([0.0, 0.0, 8.0])
    cam = (look_at(eye, eye + (np.cos(0.4), np.sin(0.4), -0.25)),
           perspective(np.radians(50.0), 16 / 9, 0.1, 1e4))
    placed = foam.whitecap_level(source)
    result = build_grid(cam, source, time=6.0, resolution=(257, 257), crest=placed)
    xy = result.base
    lod = result.lod.reshape(xy.shape[1:])
    mesh = source.foam_cue(xy, 6.0, lod, grid=np.stack(result.surface[:2]))[1:-1, 1:-1]
    crest = source.grid_cue(xy, result.crest[1])[1:-1, 1:-1]
    lod = lod[1:-1, 1:-1]
    assert_spreads_alike(mesh, source.foam_cue(xy[:, 1:-1, 1:-1], 6.0, lod), lod)
    assert_spreads_alike(crest, foam.crest_cue(source, xy[:, 1:-1, 1:-1], 6.0, lod), lod)
    assert lod.max() > placed + 1.0  # vertices finer than the crest sum's cap compared


def test_contact_foam_of_many_boxes_is_each_box_s_nearest():
    """Hundreds of turned boxes at once give every point the foam of its nearest box within
    reach, as measuring each box on its own does."""
    rng = np.random.default_rng(4)
    x, y = rng.uniform(-60.0, 60.0, (2, 6000))
    z = rng.uniform(-1.0, 1.0, 6000)
    unit = np.array([[a, b, c] for a in (0, 1) for b in (0, 1) for c in (0, 1)], float)
    boxes = []
    for _ in range(300):
        turn = rng.uniform(0.0, np.pi)
        rot = np.array([[np.cos(turn), -np.sin(turn), 0.0], [np.sin(turn), np.cos(turn), 0.0],
                        [0.0, 0.0, 1.0]])
        size = rng.uniform(0.2, 4.0, 3)
        boxes.append((unit - 0.5) * size @ rot.T + (*rng.uniform(-60.0, 60.0, 2), 0.0))
    boxes = np.array(boxes)[:, [0, 1, 3, 2, 4, 5, 7, 6]]  # Blender's bound_box order
    want = np.zeros(6000)
    p = np.stack([x, y, z], axis=-1)
    for corners in boxes:
        edges = corners[[4, 3, 1]] - corners[0]
        t = np.clip((p - corners[0]) @ edges.T / (edges * edges).sum(axis=1), 0.0, 1.0)
        near = np.clip(1.0 - np.linalg.norm(p - corners[0] - t @ edges, axis=1) / 1.5, 0.0, 1.0)
        want = np.maximum(want, near * near)
    cover = foam.contact_foam(x, y, z, boxes, 1.5)
    assert (want > 0.0).sum() > 200 and cover == pytest.approx(want, abs=1e-6)


def test_contact_foam_of_boxes_beyond_the_points():
    """Boxes whose rectangles lie past every point in y (or x) while overlapping them in the
    other give no foam and raise nothing; one beside them still rings its points."""
    x, y = np.meshgrid(np.linspace(0.0, 10.0, 21), np.linspace(0.0, 10.0, 21))
    unit = np.array([[a, b, c] for a in (0, 1) for b in (0, 1) for c in (0, 1)], float)
    unit = unit[[0, 1, 3, 2, 4, 5, 7, 6]]  # Blender's bound_box order
    far = [unit + (2.0, 40.0, -0.5), unit + (40.0, 2.0, -0.5), unit + (-30.0, -30.0, -0.5)]
    assert not foam.contact_foam(x, y, np.zeros_like(x), far, 1.0).any()
    ringed = foam.contact_foam(x, y, np.zeros_like(x), [*far, unit + (4.0, 4.0, -0.5)], 1.0)
    assert ringed.max() == 1.0 and ringed.sum() > 4.0


class _Given:
    """A source whose cue is the active foam given by hand, `event(time)`, everywhere."""

    choppiness = 0.0

    def __init__(self, event):
        self.event = event

    def foam_cue(self, xy, time, lod=None, grid=None):
        return np.full(xy.shape[1:], self.event(time), np.float32)


def _residual_after(event, tau, times):
    """Residual foam at `times` of one point whose active foam is `event(when)`."""
    xy = np.zeros((2, 1, 1))
    return np.array([float(residual_foam.residual(
        _Given(event), xy, None, t, lambda lod: lambda cue: cue.ravel(), tau)[0])
        for t in times])


def test_residual_foam_decays_as_callaghan_s_patches():
    """A breaker active for T_A leaves its patch whole (R = 1 as it stops) and the patch's
    area then decays as e^(-age / tau) (Callaghan et al. 2012), continuously from frame to
    frame; a sea whose active share is steady lays R = A tau / T_A, the window's part of it
    placed (the rest, aged, is the shader's streaks); and tau grows with the breakers' length
    within Callaghan's 0.5-8 s."""
    tau, start = 2.0, 10.0
    t_a = residual_foam.ACTIVE_TIME

    def event(when):
        return 1.0 if start <= when < start + t_a else 0.0
    times = np.arange(start - 1.0, start + 6.0, 1.0 / 48.0)
    r = _residual_after(event, tau, times)
    assert r.max() == pytest.approx(1.0, abs=0.05) and r[times < start].max() == 0.0
    # after the last sample of the breaker has ramped in, before the window's last step
    # tapers the patch out
    step = tau / residual_foam.SAMPLES_PER_DECAY
    after = (times < start + residual_foam.WINDOW * tau - step) & (r < 0.95) & (
        times > start + t_a + step)
    assert after.sum() > 48  # a second of the decay
    fitted = -1.0 / np.polyfit(times[after], np.log(r[after]), 1)[0]
    assert fitted == pytest.approx(tau, rel=0.15), fitted
    assert np.abs(np.diff(r)).max() < 0.1  # no jumps between frames
    steady = _residual_after(lambda when: 0.01, tau, np.arange(20.0, 23.0, 0.1))
    placed = 1.0 - residual_foam.aged_share()
    assert 0.8 < placed < 0.9  # most of it placed where it fell
    assert steady == pytest.approx(0.01 * tau / t_a * placed, rel=0.02)
    taus = [residual_foam.decay_time(SpectralField(SeaState(wind_speed=u))) for u in (6.7, 19.0)]
    assert 0.5 <= taus[0] < taus[1] <= 8.0, taus


@pytest.mark.parametrize("force", [4, 6, 8, 10])
def test_active_and_residual_foam_cover_monahan_s_share(force):
    """Over a patch of sea (a 3 m grid, 480 m across), at several times, the whitecaps active now
    and the foam they left over the past seconds (and the aged foam's streaks, over the whole
    sea) cover together Monahan and O'Muircheartaigh's 1.59e-5 U^2.55 within 0.5-2x (the
    issue's measure), the residual most of it."""
    preset = sea_states.sea_state(force)
    source = SpectralField(SeaState(wind_speed=preset.wind_speed, fetch=preset.fetch),
                           choppiness=preset.choppiness, seed=2)
    xy = np.stack(np.meshgrid(np.arange(160) * 3.0, np.arange(160) * 3.0))
    lod = np.full(xy.shape[1:], band_limit.lod_for_spacing(source.wave_scale, 3.0), np.float32)
    shares = []
    for t in (20.0, 27.3, 34.9):
        placed = foam.whitecap_level(source)
        sideways, crest = source.sample(xy, t, lod, (1, 2), crest=placed)
        moved = xy + sideways  # a frame's grid (build_grid), here square
        grid = types.SimpleNamespace(base=xy, surface=(moved[0], moved[1], None), lod=lod,
                                     crest=(placed, crest))
        active, residual = foam.foam_field(source, grid, t, preset.wind_speed, True, [], 0.0)
        shares.append((active.mean(), (active + (1.0 - active) * residual).mean()))
    active, total = np.mean(shares, axis=0)
    total += (1.0 - total) * foam.foam_look(source, preset.wind_speed)[2]
    want = effects.whitecap_coverage(preset.wind_speed)
    assert 0.5 * want <= total <= 2.0 * want, (force, active, total, want)
    assert total > 2.0 * active
