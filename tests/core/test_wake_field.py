"""The wakes the grid draws (projgrid_addon/wake_field.py): a hull's steady wake laid along its
course, against the exact sum it is read from (wakes.py) and against what a wake is: Kelvin's
cusp line at 19.47 degrees at hull Froude numbers below 0.4, transverse waves 2 pi U^2 / g
long, its energy within 25 degrees of the track; it follows a turning course, changes
continuously as the hull speeds up, and is nothing for a hull at rest."""

from types import SimpleNamespace

import numpy as np
import pytest

from projgrid_addon import steady_wake, wake_field, wakes

G, T = 9.81, 60.0


def straight(u, length, beam, t=T, draft=1.0):
    times = np.arange(t - wakes.WINDOW, t + 1e-9, 0.1)
    return wake_field.course("hull", times, u * times, np.zeros_like(times), draft, length,
                             beam)


def exact(u, length, beam, xs, ys, t=T):
    """The exact moving wake (wakes.raster_heights, the dent taken out) of the row of
    patches wake_field.hull makes of the hull, both patch counts weighted as it reads them."""
    sigma, patches, peak = steady_wake.hull(length, beam, u)
    x, y = np.meshgrid(xs, ys)
    out = np.zeros_like(x)
    low = int(np.floor(patches))
    for count, weight in ((low, 1.0 + low - patches), (low + 1, patches - low)):
        for i in range(count):
            ahead = (i - (count - 1) / 2.0) * steady_wake.PATCH * steady_wake.CELL * sigma

            def path(taus, ahead=ahead):
                return np.stack([u * taus + ahead, np.zeros_like(taus)])
            h = wakes.raster_heights(xs, ys, t, path, 1.0, 4.0 * sigma, 60.0)
            h += np.exp(-((x - u * t - ahead) ** 2 + y**2) / (2.0 * sigma**2))
            out += h * peak / count * weight
    return out


@pytest.mark.parametrize("u, length, beam", [(5.0, 10.0, 3.0), (8.0, 20.0, 5.0)])
def test_a_straight_course_s_wake_is_the_hull_s_exact_wake(u, length, beam):
    """Where the exact sum's 60 s have formed the wake (a quarter of the 40 s course behind
    the hull), the steady wake read along the course is within a tenth of its rms of it."""
    xs = np.arange(u * T - 0.25 * u * wakes.WINDOW, u * T + 15.0, 0.5)
    ys = np.arange(-40.0, 40.0, 0.5)
    field = wake_field.heights(straight(u, length, beam), np.stack(np.meshgrid(xs, ys)))
    want = exact(u, length, beam, xs, ys)
    assert (field - want).std() < 0.1 * want.std(), ((field - want).std(), want.std())


def kelvin(u, length, t=T):
    """(cusp angle, transverse wavelength, share of the energy within 25 degrees) of a hull
    of `length` (beam a quarter of it) moving along +x, from its wake's heights on a
    lattice of a 40th of the transverse wavelength, rows 3 wavelengths behind it and on.
    The cusp line per row: outward from the cusp waves' crest (the largest beyond 8 degrees)
    where the wake falls to Ai(0) / max Ai = 0.662 of it (the caustic of the Airy function
    the cusp waves are, which lies on the cusp line; its largest crest lies inside)."""
    lam = 2.0 * np.pi * u * u / G
    behind = np.arange(3.0 * lam, 0.7 * u * wakes.WINDOW, lam / 40.0)
    across = np.arange(0.0, 0.5 * behind.max(), lam / 40.0)
    bx, by = np.meshgrid(u * t - behind, across, indexing="ij")
    course = straight(u, length, length / 4.0, t)
    h = wake_field.heights(course, np.stack([bx, by]))
    angle = np.degrees(np.arctan2(by, u * t - bx))
    cusp_waves = np.where((angle > 8.0) & (angle < 35.0), np.abs(h), 0.0)
    edges = []
    for row, k in enumerate(np.argmax(cusp_waves, axis=1)):
        out = np.flatnonzero(np.abs(h[row, k:]) < 0.662 * cusp_waves[row, k])
        edges.append(angle[row, k + out[0]])
    track = u * t - np.arange(2.0 * lam, 0.6 * u * wakes.WINDOW, lam / 50.0)
    along = wake_field.heights(course, np.stack([track, np.zeros_like(track)]))
    crossings = track[np.flatnonzero(np.diff(np.sign(along)) != 0)]
    energy = h * h * np.where(by == 0.0, 1.0, 2.0)  # both sides
    return (float(np.median(edges)), 2.0 * float(np.mean(-np.diff(crossings))),
            float(energy[angle <= 25.0].sum() / energy.sum()))


@pytest.mark.parametrize("u, length", [(5.0, 20.0), (10.0, 80.0)])
def test_kelvin_s_cusp_line_transverse_waves_and_wedge(u, length):
    """Hull Froude number 0.36 at 5 and 10 m/s: the cusp line 19.47 degrees from the track
    (within 1.5), the transverse waves 2 pi U^2 / g long (within 5 %), at least 80 % of the
    wake's energy within 25 degrees of the track."""
    assert u / np.sqrt(G * length) < 0.4
    cusp, wavelength, within = kelvin(u, length)
    assert cusp == pytest.approx(np.degrees(np.arcsin(1.0 / 3.0)), abs=1.5)
    assert wavelength == pytest.approx(2.0 * np.pi * u * u / G, rel=0.05)
    assert within >= 0.8


def turning(t):
    """A hull along +x for 20 s at 5 m/s, then a quarter circle (30 m) to +y, then +y."""
    u, radius = 5.0, 30.0
    times = np.arange(t - wakes.WINDOW, t + 1e-9, 0.1)
    turn = np.clip(times - 20.0, 0.0, np.pi / 2.0 * radius / u) * u / radius
    x = u * np.minimum(times, 20.0) + radius * np.sin(turn)
    y = radius * (1.0 - np.cos(turn)) + u * np.maximum(times - 20.0 - np.pi / 2.0 * radius
                                                       / u, 0.0)
    return wake_field.course("turning", times, x, y, 1.0, 10.0, 3.0)


def test_a_turning_hull_leaves_a_curved_wake():
    """After a quarter turn the wake lies along the course the hull took: beside its first
    leg (along +x, 95-135 m of course behind it) as strong as beside a straight course the
    same distance behind (within 0.5-2x), and where a wake drawn straight behind the hull now
    (along -y) would lie, next to nothing."""
    turned = turning(35.0)  # on the last leg for 5.6 s, 28 m; the turn 47 m
    along = np.arange(95.0, 135.0, 0.5)
    straight_rms, turned_rms, wrong_rms = [], [], []
    for offset in (-4.0, 4.0):
        first_leg = np.stack([100.0 - (along - 75.0), np.full_like(along, offset)])
        turned_rms.append(wake_field.heights(turned, first_leg))
        reference = straight(5.0, 10.0, 3.0, 35.0)
        behind = np.stack([5.0 * 35.0 - along, np.full_like(along, offset)])
        straight_rms.append(wake_field.heights(reference, behind))
        wrong = np.stack([np.full_like(along, 130.0 + offset), 58.0 - along])
        wrong_rms.append(wake_field.heights(turned, wrong))
    rms = [float(np.sqrt(np.mean(np.square(v)))) for v in (turned_rms, straight_rms, wrong_rms)]
    assert 0.5 < rms[0] / rms[1] < 2.0, rms
    assert rms[2] < 0.1 * rms[1], rms


def test_a_wake_changes_continuously_as_its_hull_speeds_up():
    """A hull speeding up from 3 to 9 m/s (across rungs of the Froude ladder and patch
    counts): from one frame to the next its wake changes by less than a sixth of its height
    (as a steady hull's, 0.1 here); each frame the same alone or after others."""
    def accelerating(t):
        times = np.arange(t - wakes.WINDOW, t + 1e-9, 0.1)
        x = 3.0 * times + 0.15 * np.clip(times - 30.0, 0.0, 20.0) ** 2
        return wake_field.course("a", times, x, np.zeros_like(x), 1.0, 10.0, 3.0)
    xy = np.stack(np.meshgrid(np.arange(150.0, 300.0, 0.5), np.arange(-40.0, 40.0, 0.5)))
    frames = [wake_field.heights(accelerating(45.0 + f / 24.0), xy) for f in range(48)]
    height = max(np.abs(f).max() for f in frames)
    assert np.abs(np.diff(frames, axis=0)).max() < height / 6.0
    assert np.array_equal(frames[7], wake_field.heights(accelerating(45.0 + 7 / 24.0), xy))


def test_a_hull_at_rest_makes_none_and_a_jump_starts_its_course_anew():
    """At rest (or slower than MOVING) no wake; a course cut by a jump (a key 200 m on in a
    frame) is kept from the jump on: nothing is drawn along the course before it."""
    times = np.arange(T - wakes.WINDOW, T + 1e-9, 0.1)
    still = wake_field.course("s", times, np.full_like(times, 5.0), np.zeros_like(times), 1.0,
                              10.0, 3.0)
    xy = np.stack(np.meshgrid(np.arange(-20.0, 20.0, 0.5), np.arange(-20.0, 20.0, 0.5)))
    assert not wake_field.heights(still, xy).any()
    x = 5.0 * times + np.where(times > T - 10.0, 200.0, 0.0)
    cut = wake_field.course("c", times, x, np.zeros_like(x), 1.0, 10.0, 3.0)
    assert cut.times[0] > T - 10.0
    before = np.stack(np.meshgrid(np.arange(5.0 * (T - 40.0), 5.0 * (T - 10.0), 0.5),
                                  np.arange(-10.0, 10.0, 0.5)))
    assert np.abs(wake_field.heights(cut, before)).max() < 1e-6
    after = xy + np.array([[[5.0 * T + 190.0]], [[0.0]]])
    assert np.abs(wake_field.heights(cut, after)).max() > 0.1
    # constant interpolation: 5 m a second, in one step each (25 m/s for 0.2 s)
    steps = 5.0 * np.floor(np.round(times, 6))
    stepping = wake_field.course("k", times, steps, np.zeros_like(steps), 1.0, 10.0, 3.0)
    assert not wake_field.heights(stepping, xy + np.array([[[steps[-1]]], [[0.0]]])).any()


def test_the_grid_holds_the_wake_where_its_vertices_resolve_it():
    """draw: the wake added whole where its transverse waves span four vertex spacings or
    more, none where two or fewer (the band limit); the heights added to the vertices and to
    the surface alike."""
    course = straight(5.0, 10.0, 3.0)
    x, y = np.meshgrid(np.arange(250.0, 300.0, 1.0), np.arange(-10.0, 10.0, 1.0))
    wavelength = 2.0 * np.pi * 25.0 / G
    spacing = np.where(x < 275.0, wavelength / 4.0, wavelength / 2.0)
    wave_scale = 100.0
    lod = np.log2(wave_scale / (2.0 * spacing)).astype(np.float32)
    result = SimpleNamespace(surface=(x, y, np.zeros_like(x)), lod=lod.ravel(),
                             positions=np.zeros((x.size, 3), np.float32))
    added, _, _ = wake_field.draw(result, [course], wave_scale)
    full = wake_field.heights(course, np.stack([x, y]))
    assert np.abs(added - np.where(x < 275.0, full, 0.0)).max() < 1e-5
    assert np.abs(full[x < 275.0]).max() > 0.1
    assert np.array_equal(result.positions[:, 2], added.ravel())
    assert np.array_equal(result.surface[2], added)


def test_a_fine_grid_reads_the_wake_on_every_other_row_and_column():
    """read_grid: on a grid finer than a COARSE-th of the transverse wave the wake (and its
    foam) read on every other row and column and interpolated is within 3 % of its height of
    the wake read at every vertex; where coarser, it is read at every vertex."""
    course = straight(5.0, 10.0, 3.0)
    wavelength = 2.0 * np.pi * 25.0 / G
    x, y = np.meshgrid(np.arange(200.0, 300.0, 0.2), np.arange(-30.0, 30.0, 0.2))
    spacing = np.where(x < 280.0, wavelength / (2.0 * wake_field.COARSE), wavelength)
    lod = np.log2(100.0 / (2.0 * spacing)).astype(np.float32)  # wave scale 100 m
    got = wake_field.read_grid(course, x, y, lod, np.log2(wavelength / 100.0))
    want = wake_field.read(course, np.stack([x, y]), foam=True)
    for g, w in zip(got, want, strict=True):
        assert np.abs(g - w).max() <= 0.03 * np.abs(w).max()
        assert np.array_equal(g[x >= 280.0], w[x >= 280.0])
