"""The residual foam's past on canonical cameras' grids (past_grid.py): frames of a camera
moving along its heading share them, a frame's foam is the same whatever was drawn before, it
changes without a jump as the camera crosses the lattice's lines, and it is as much foam as
the frame's own grid takes."""

import numpy as np
import pytest

from projgrid_addon import foam, past_grid, residual_foam, sea_states
from projgrid_addon.camera import Camera, look_at, perspective
from projgrid_addon.displaceable_volume import Extent
from projgrid_addon.grid_points import grid_points, grid_uv_of
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.projector import aim_projector
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

PRESET = sea_states.sea_state(8)
PROJ = perspective(2.0 * np.arctan(np.tan(np.radians(27.2)) * 9 / 16), 16 / 9, 0.1, 1e4)


def gale(seed=5):
    state = SeaState(wind_speed=PRESET.wind_speed, fetch=PRESET.fetch)
    return SpectralField(state, choppiness=PRESET.choppiness, seed=seed)


def camera(eye, heading=90.0, pitch=-4.0, proj=PROJ):
    h, p = np.radians(heading), np.radians(pitch)
    eye = np.asarray(eye, np.float64)
    return Camera(look_at(eye, eye + (np.cos(h) * np.cos(p), np.sin(h) * np.cos(p), np.sin(p))),
                  proj)


def frame(source, cam, t, resolution=(129, 129), dolly=True, band_limit=True, level=0.0,
          elevation=0.0):
    result = build_grid(cam, source, level, t, resolution, elevation, band_limit,
                        crest=foam.whitecap_level(source))
    return result, foam.foam_field(source, result, t, PRESET.wind_speed, True, [], level, dolly)


def own_grid(source, result, t):
    """The residual a frame takes on its own grid (residual_foam.residual)."""
    placed, made = foam.crest_calibration(source, t, PRESET.wind_speed)
    share = (1.0 - foam.streaks.streak_share(PRESET.wind_speed)) / (
        1.0 - residual_foam.aged_share())
    return residual_foam.residual(
        source, result.base, result.lod.reshape(result.base.shape[1:]), t,
        lambda at: foam.at_thresholds(at, made), residual_foam.decay_time(source), None, share,
        placed)


@pytest.fixture
def counted(monkeypatch):
    """The past cues made (residual_foam.cue_at's times) and the frames that took their past on
    their own grid."""
    made, own = [], []
    cue_at, residual = residual_foam.cue_at, past_grid.residual

    def cues(source, xy, when, lod, top=None):
        made.append(len(when) if isinstance(when, tuple) else 1)
        return cue_at(source, xy, when, lod, top)

    def on_own(*args, **kwargs):
        own.append(1)
        return residual(*args, **kwargs)
    monkeypatch.setattr(residual_foam, "cue_at", cues)
    monkeypatch.setattr(past_grid, "residual", on_own)
    return made, own


def test_the_canonical_cameras_stand_behind_on_a_lattice_along_the_heading():
    """A camera a share f of a step past a line of its lattice has the canonical cameras of
    that line and the one before, weighted f and 1 - f: at its height, looking its way, each
    on its line; crossing a line, the weights hand over (all of the line's at it, from either
    side); a sideways move, others; a camera looking down or rolled, its heading the top of
    its screen's or its view's."""
    for heading in (90.0, 33.0, -150.0):
        h = np.radians(heading)
        ahead = np.array([np.cos(h), np.sin(h), 0.0])
        start = np.array([1234.5, -987.25, 5.0])
        step = 2.0 ** np.floor(np.log2(past_grid.SNAP * 5.0))
        views = set()
        for d in np.linspace(0.0, 3.0 * step, 25):
            cam = camera(start + d * ahead, heading)
            made = past_grid.canonical_cameras(cam, 0.0)
            along = (cam.position @ ahead) / step
            past = along - np.floor(along)
            assert sum(w for _, w in made) == pytest.approx(1.0)
            for canon, weight in made:
                line = (canon.position @ ahead) / step
                assert abs(line - np.round(line)) < 1e-6
                behind = along - line
                assert weight == pytest.approx(past if behind < 1.0 else 1.0 - past, abs=1e-6)
                assert 0.0 <= behind < 2.0 + 1e-9
                assert abs(canon.position[2] - 5.0) < 1e-4
                assert np.allclose(canon.forward, cam.forward, atol=1e-8)
                views.add(canon.view.tobytes())
        assert 4 <= len(views) <= 5  # the lines behind the 3 steps' start to its end
        at_line = start + (np.ceil(start @ ahead / step) * step - start @ ahead) * ahead
        weights = [{np.round((c.position @ ahead) / step): w
                    for c, w in past_grid.canonical_cameras(camera(at_line + e * ahead,
                                                                   heading), 0.0)}
                   for e in (-1e-6, 1e-6)]
        line = np.round(at_line @ ahead / step) - 1.0
        assert weights[0][line] == pytest.approx(1.0, abs=1e-6)
        assert weights[1][line] == pytest.approx(1.0, abs=1e-6)
        side = past_grid.canonical_cameras(camera(start + (0.3, 0.0, 0.0), heading), 0.0)
        assert not {c.view.tobytes() for c, _ in side} & views
    down = Camera(look_at((0.0, 0.0, 50.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)), PROJ)
    canon, _ = past_grid.canonical_cameras(down, 0.0)[0]
    assert abs(canon.position[0]) < 1e-9  # moved along the screen's top, +y
    rolled = camera((0.0, 0.0, 5.0), 90.0, -10.0).view.copy()
    turn = np.eye(4)
    turn[:2, :2] = [[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]]
    canon, _ = past_grid.canonical_cameras(Camera(turn @ rolled, PROJ), 0.0)[0]
    assert abs(canon.position[0]) < 1e-9  # along the view, not the rolled right axis


def test_grid_uv_of_inverts_the_grid_s_points_and_kept_points_are_the_grid_s():
    """grid_points' points map back to their columns' u and rows' v; those of kept columns
    and rows are the whole grid's, band limits and all."""
    args = (camera((0.0, 0.0, 8.0), 60.0, -10.0), 0.0, Extent(2.0, 2.0, 1.0))
    for resolution in ((33, 17), (64, 33)):
        made = grid_points(*args, resolution, 0.0, aim_projector, np.zeros(3), 40.0)
        u, v = grid_uv_of(made.c, made.xy)
        assert np.allclose(u, np.broadcast_to(made.u, u.shape), atol=1e-9)
        assert np.allclose(v, np.broadcast_to(made.v, v.shape), atol=1e-9)
        columns, rows = np.array([0, 3, 7, resolution[0] - 1]), np.array([1, 2, resolution[1] - 1])
        kept = grid_points(*args, resolution, 0.0, aim_projector, np.zeros(3), 40.0,
                           (columns, rows))
        assert np.array_equal(kept.xy, made.xy[:, rows][:, :, columns])
        assert np.array_equal(kept.lod, made.lod[rows][:, columns])


def test_a_dolly_s_frames_share_their_past(counted):
    """A gale's camera moving 2 m a frame along its heading 5 m up: frames make no past cue
    but where a new line enters (each 8 m: a frame in four) or a new lattice time begins, and
    none takes its past on its own grid."""
    made, own = counted
    source = gale()
    per_frame = []
    for k in range(13):
        made.clear()
        frame(source, camera((0.0, 2.0 * k + 0.5, 5.0)), 30.0 + k / 24.0)
        per_frame.append(sum(made))
    assert not own
    window = len(residual_foam.samples(30.0, residual_foam.decay_time(source)))
    assert sum(n >= window - 1 for n in per_frame[1:]) <= 4, per_frame
    assert sum(n <= 2 for n in per_frame[1:]) >= 8, per_frame


def test_a_frame_s_residual_is_the_same_alone_or_after_others():
    """A frame drawn after others (their canonical grids' cues kept, some shared with it, some
    of other heights and views, or of its place but another lens, resolution, sea level or
    projector elevation) draws what it draws alone: bit-identical."""
    warm = gale()
    wide = perspective(np.radians(60.0), 16 / 9, 0.1, 1e4)
    for k in range(3):
        frame(warm, camera((0.0, 0.6 * k, 5.0)), 30.0 + k / 24.0)
        frame(warm, camera((3.0, 0.6 * k, 7.0), 80.0, -8.0), 30.0 + k / 24.0)
    t = 30.0 + 3 / 24.0
    frame(warm, camera((0.0, 2.0, 5.0), proj=wide), t)
    frame(warm, camera((0.0, 2.0, 5.0)), t, (129, 65))
    frame(warm, camera((0.0, 2.0, 5.0)), t, elevation=3.0)
    frame(warm, camera((0.0, 2.0, 5.5)), t, level=0.5)
    after = frame(warm, camera((0.0, 2.0, 5.0)), 30.0 + 3 / 24.0)[1]
    alone = frame(gale(), camera((0.0, 2.0, 5.0)), 30.0 + 3 / 24.0)[1]
    assert after[1].max() > 0.0
    assert all(np.array_equal(a, b) for a, b in zip(after, alone, strict=True))


def _change(before, after):
    """How much the residual changed between two frames at the water's points: the later
    grid's points read on the earlier grid (bilinear), mean |change| over the mean."""
    (r0, f0), (r1, f1) = before, after
    u, v = r0.spacing
    pu, pv = grid_uv_of(r0.projector.corner_points(0.0), r1.base)
    i = np.interp(pu, u, np.arange(len(u)), left=np.nan, right=np.nan)
    j = np.interp(pv, v, np.arange(len(v)), left=np.nan, right=np.nan)
    ok = np.isfinite(i) & np.isfinite(j)
    grid = f0.reshape(len(v), len(u))
    i0 = np.minimum(i[ok].astype(int), len(u) - 2)
    j0 = np.minimum(j[ok].astype(int), len(v) - 2)
    fi, fj = i[ok] - i0, j[ok] - j0
    old = ((grid[j0, i0] * (1 - fi) + grid[j0, i0 + 1] * fi) * (1 - fj)
           + (grid[j0 + 1, i0] * (1 - fi) + grid[j0 + 1, i0 + 1] * fi) * fj)
    new = f1.reshape(len(v), len(u))[ok]
    return np.abs(new - old).mean() / (0.5 * (new.mean() + old.mean()))


def test_the_residual_changes_without_a_jump_at_the_lattice_s_lines(monkeypatch):
    """Frame to frame along a dolly (5 m up, 2 m a frame, crossing three lines), the residual
    at the water's points changes no more than on the frames' own grids (whose coarse points
    move with the camera), at a line as between."""
    def changes():
        source, frames = gale(seed=3), []
        for k in range(14):
            t = 40.0 + k / 24.0
            result, (_, residual) = frame(source, camera((0.0, 2.0 * k, 5.0)), t, (257, 257))
            frames.append((result, residual))
        return np.array([_change(a, b) for a, b in zip(frames[:-1], frames[1:], strict=True)])
    ours = changes()
    monkeypatch.setattr(past_grid, "_canonical", lambda *args: None)
    theirs = changes()
    assert ours.max() <= theirs.max() and np.median(ours) <= np.median(theirs), (ours, theirs)


@pytest.mark.parametrize("height, pitch", [(5.0, -4.0), (40.0, -12.0), (2.0, 3.0)])
def test_the_residual_read_on_canonical_grids_is_as_much_as_the_frame_s_own(counted, height,
                                                                          pitch):
    """Over frames at places all through a step (each a time of its own, many breakers), the
    residual the canonical grids give is the frame's own grid's within 25 %: where the
    canonical grids' points fall is all that differs."""
    _, own = counted
    source = gale(seed=3)
    step = 2.0 ** np.floor(np.log2(past_grid.SNAP * height))
    ours = theirs = 0.0
    for k in range(12):
        t = 30.0 + 1.37 * k
        cam = camera((400.0 * k, step * ((0.37 * k) % 1.0), height), 90.0, pitch)
        result, (_, residual) = frame(source, cam, t, (257, 257))
        ours += residual.mean()
        theirs += own_grid(source, result, t).mean()
    assert theirs > 0.0 and not own
    assert 0.75 <= ours / theirs <= 1.25, ours / theirs


@pytest.mark.parametrize("pitch", [-25.0, -30.0, -60.0, -90.0])
def test_a_camera_looking_down_takes_its_past_on_its_own_grid(counted, pitch):
    """A camera looking down steeply (5 m and 20 m up, frames through a step): the canonical
    cameras, a step or two behind, do not see all it sees, so every frame takes the residual
    its own grid takes, exactly."""
    made, own = counted
    source = gale()
    for height in (5.0, 20.0):
        step = 2.0 ** np.floor(np.log2(past_grid.SNAP * height))
        for f in (0.1, 0.5, 0.95):
            own.clear()
            cam = camera((0.0, step * (f + 100.0), height), 90.0, pitch)
            result, (_, residual) = frame(source, cam, 50.0 + f)
            assert own
            assert np.array_equal(residual, own_grid(source, result, 50.0 + f))


def test_a_camera_that_does_more_than_dolly_takes_its_past_on_its_own_grid(counted):
    """A camera that turns, climbs or zooms in time (FrameInputs.dolly false) would have new
    canonical cameras each frame: it takes the residual its own grid takes, exactly."""
    _, own = counted
    source = gale()
    cam = camera((0.0, 3.0, 5.0))
    result, (_, residual) = frame(source, cam, 30.0, dolly=False)
    assert own and residual.max() > 0.0
    assert np.array_equal(residual, own_grid(source, result, 30.0))


def test_a_grid_without_a_band_limit_takes_its_past_on_its_own_grid(counted):
    """Without a band limit the whitecaps' thresholds do not follow the grid's spacing, so
    another camera's grid would foam differently: such a grid takes its own grid's past."""
    _, own = counted
    source = gale()
    result, (_, residual) = frame(source, camera((0.0, 3.0, 5.0)), 30.0, band_limit=False)
    assert own and residual.max() > 0.0
    assert np.array_equal(residual, own_grid(source, result, 30.0))


@pytest.mark.parametrize("height, clip", [(5.0, 100.0), (20.0, 200.0), (100.0, 1000.0)])
def test_a_frame_takes_one_path_all_through_a_step_whatever_its_far_clip(counted, height, clip):
    """A camera whose far clip ends on the sea (a canonical camera behind it sees less far):
    every frame through a step takes its past the same way, on the canonical grids or on its
    own, so the foam does not jump between the two within a step."""
    _, own = counted
    source = gale()
    proj = perspective(2.0 * np.arctan(np.tan(np.radians(27.2)) * 9 / 16), 16 / 9, 0.1, clip)
    step = 2.0 ** np.floor(np.log2(past_grid.SNAP * height))
    paths = []
    for f in (0.05, 0.3, 0.55, 0.8, 0.97):
        own.clear()
        frame(source, camera((0.0, step * (f + 10.0), height), 90.0, -8.0, proj), 30.0 + f)
        paths.append(bool(own))
    assert len(set(paths)) == 1, paths
