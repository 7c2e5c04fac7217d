"""Spindrift and spray torn off the breaking crests by the wind: from Beaufort 8 ("edges of
crests begin to break into spindrift"; WMO), more at 9 ("spray may affect visibility") and
beyond. Particles, each a pure function of the settings and the time, as Jensen and Golias
(2001, Particle System) make them: a particle leaves the surface with the water's velocity
where it is spawned and some turbulence, then gravity and the wind move it.

Launches are sums over a past window, never state: launch sites on world lattices (each site
jittered by a hash of its indices: fixed in the sea, not the camera), launch times on an
absolute lattice STEP s apart. As the projected grid's detail follows the camera, so does the
spray's: ring 0's sites lie CELL m apart within REACH of the camera, each further ring's twice
as far apart out to twice as far, their puffs twice as wide (fewer, larger puffs a pixel still
resolves), the rings cross-fading over FADE of an octave of distance and the last thinning
out over its own (`ring_weight`): far off, spray is a veil over the sea, not puffs standing on
the horizon. A launch throws its puffs from along the crest through its site's cell (a
veil across the wind, not a dome over one point). A site launches at a lattice
time with the probability of the active whitecap share there then (the frame's whitecaps,
foam.at_thresholds, from the cue at the site before the choppy displacement) times the wind's
`spray_rate`, and throws PER_LAUNCH puffs (clouds of droplets), each over the step after it
(the crest carrying the site at the sea's peak phase speed meanwhile), so a breaking crest
streams spray.

A droplet of relaxation time tau (drag toward the wind W: Stokes' tau = rho_w d^2 / (18 mu_air),
0.02-1.6 s for spume droplets of 70-700 um, less past Stokes' law: `settling`) and
gravity g moves, from x0 with velocity v0, as

    x(a) = x0 + (W + g tau) a + (v0 - W - g tau) tau (1 - e^(-a / tau))

and the air's turbulence spreads it as a random walk (sqrt(2 K a) of a fixed normal draw): the
small droplets ride the wind as a mist, the large fall back within a second. A puff's droplets
are of many sizes (tau spanning SIZES): the drag sorts them along the wind, so each puff is
drawn as SORTED points of its smallest to largest droplets, which leave the crest together
and draw out into a streamer (spindrift's streaks), the small ahead, the large lagging low
(in the STREAKED nearest rings: further off, a streamer is no longer than a puff is wide)."""

from functools import lru_cache

import numpy as np

from . import foam, noise, residual_foam, spectrum
from .effects import SPRAY_ONSET

SPRAY_FULL = 24.5  # m/s: Beaufort 9's most ("spray may affect visibility"): every breaker sprays
CELL = 2.0  # m between launch sites
BLOCK = 16  # sites a block has each way (the unit launches are kept in)
STEP = 0.5  # s between launch times
LIFE = 2.0  # s a droplet is drawn at most (fading over its life)
REACH = 150.0  # m from the camera (along the sea) ring 0 reaches
RINGS = 3  # lattices of launch sites, each twice the last's spacing, reach and puffs
FADE = 0.25  # of an octave of distance: the rings' cross-fade
MARGIN = 60.0  # m beside the view's wedge whose sites' spray the wind may carry into view
PER_LAUNCH = 16  # puffs a launch throws
TAU = (0.05, 0.5)  # s: a puff's droplets' mean Stokes time (130-400 um), log-uniform
SORTED = 4  # points a near puff is drawn with: its droplets, sorted by size along the wind
STREAKED = 1  # rings whose puffs are drawn as streamers (beyond, a streamer is a puff wide)
SIZES = 10.0  # the ratio of a puff's largest droplets' Stokes time to its smallest's
CREST_SPEED = 0.8  # of the peak phase speed: the water's velocity on a breaking crest
RISE = (0.2, 1.0)  # m/s: launch speed upward (a crest's orbital velocity is level), uniform
TURBULENCE = 1.0  # m/s: the launch velocity's spread each way (normal)
DIFFUSIVITY = 0.5  # m^2/s: the air's eddy diffusivity near the crests (K)
# of the walk along the sea, the walk upward: the surface layer's vertical eddies are half as
# strong as those along the wind (sigma_w / sigma_u = 1.25 / 2.4; Panofsky and Dutton 1984)
VERTICAL = 0.52
RADIUS = (0.17, 0.43)  # m: a puff's radius at launch (a cloud of droplets), uniform
PUFF_GROWTH = 0.5  # of the turbulence's spread sqrt(2 K age): how a puff's radius grows
GRAVITY = np.array([0.0, 0.0, -spectrum.GRAVITY])
WATER_DENSITY, AIR_DENSITY, AIR_VISCOSITY = 1025.0, 1.22, 1.8e-5  # kg/m^3, kg/m^3, Pa s


def spray_rate(wind_speed):
    """The chance an active whitecap's site launches spray at a lattice time: 0 below
    SPRAY_ONSET, rising linearly to 1 at SPRAY_FULL (half the breakers at the top of force 8,
    every one from force 10; the spray thickens beyond as the whitecaps do)."""
    return float(np.clip((float(wind_speed) - SPRAY_ONSET) / (SPRAY_FULL - SPRAY_ONSET),
                         0.0, 1.0))


def ring_weight(distance, ring):
    """How much of ring `ring`'s spray is drawn at `distance` (m) from the camera along the
    sea: the rings, an octave of distance each beyond REACH, sum to 1 out to the last's start,
    each fading into the next over FADE of an octave, and the last thins out linearly in log
    distance to none at its reach (a puff there, 2^ring as wide, would stand on the horizon
    line as a bump from a low camera)."""
    t = np.log2(np.maximum(distance, 1e-9) / REACH) + 1.0  # ring r spans [r, r + 1)

    def inside(boundary):  # past the boundary between ring boundary - 1 and ring boundary
        return np.clip((t - boundary) / FADE + 0.5, 0.0, 1.0) if boundary > 0 else 1.0
    if ring == RINGS - 1:
        return inside(ring) * np.clip(RINGS - t, 0.0, 1.0)
    return inside(ring) - inside(ring + 1)


def view_wedge(camera):
    """(ahead, half): the camera's view along the sea (a unit (x, y)) and the half angle its
    frustum spans about it (the far corners'), or None where it looks so steeply down that
    the view surrounds its foot (every direction then shows)."""
    ahead = np.asarray(camera.forward[:2], np.float64)
    if np.hypot(*ahead) < 0.2:
        return None
    ahead = ahead / np.hypot(*ahead)
    to = camera.corners[4:, :2] - camera.position[:2]
    angles = np.abs(np.arctan2(to[:, 0] * ahead[1] - to[:, 1] * ahead[0], to @ ahead))
    half = float(angles.max())
    return None if half > np.radians(80.0) else (ahead, half)


def blocks(centre, wedge, ring=0):
    """The blocks of BLOCK x BLOCK launch sites of `ring` (their lattice indices (bx, by))
    within its reach of `centre` (x, y) and within MARGIN of the view's `wedge` (view_wedge;
    None: all around): fixed in the sea, so a moving camera keeps the rest. A still camera's
    are kept (`_blocks`)."""
    if wedge is not None:
        wedge = (float(wedge[0][0]), float(wedge[0][1])), float(wedge[1])
    return _blocks(float(centre[0]), float(centre[1]), wedge, ring)


@lru_cache(maxsize=2 * RINGS)
def _blocks(cx, cy, wedge, ring):
    size = BLOCK * CELL * 2.0**ring
    centre = np.array([cx, cy])
    reach = REACH * 2.0 ** (ring + FADE / 2.0)
    lo = np.floor((centre - reach) / size).astype(np.int64)
    n = int(np.ceil(2.0 * reach / size)) + 1
    by, bx = np.meshgrid(lo[1] + np.arange(n), lo[0] + np.arange(n), indexing="ij")
    corner = np.stack([bx.ravel(), by.ravel()]) * size
    off = np.clip(centre[:, None], corner, corner + size) - centre[:, None]  # nearest point
    far = np.hypot(*(np.maximum(abs(corner - centre[:, None]),
                                abs(corner + size - centre[:, None]))))  # farthest corner
    keep = np.hypot(*off) < reach
    if ring > 0:
        keep &= far > REACH * 2.0 ** (ring - 1 - FADE / 2.0)
    if wedge is not None:
        (ax, ay), half = wedge
        c = corner + size / 2.0 - centre[:, None]
        along, across = c[0] * ax + c[1] * ay, c[0] * ay - c[1] * ax
        outside = np.arctan2(np.abs(across), along) - half
        lateral = np.hypot(along, across) * np.sin(np.clip(outside, 0.0, np.pi / 2.0))
        keep &= lateral < MARGIN + size / np.sqrt(2.0)
    return tuple((int(x), int(y)) for x, y in zip(bx.ravel()[keep], by.ravel()[keep],
                                                  strict=True))


def sites(bx, by, ring=0):
    """(ix, iy, xy): the block's launch sites, their lattice indices and jittered points."""
    iy, ix = np.meshgrid(by * BLOCK + np.arange(BLOCK), bx * BLOCK + np.arange(BLOCK),
                         indexing="ij")
    ix, iy = ix.ravel(), iy.ravel()
    cell = CELL * 2.0**ring
    return ix, iy, np.stack([(ix + noise.uniforms(_salt(0, ring, 1), ix, iy)) * cell,
                             (iy + noise.uniforms(_salt(0, ring, 2), ix, iy)) * cell])


def _salt(seed, ring, use):
    """The hash key of one use of the random values, per seed and ring."""
    return (seed * 8 + ring) * 32 + use


def launch_times(time):
    """The lattice indices of the launch times whose droplets may still show at `time`."""
    last = int(np.floor(time / STEP))
    return range(last - int(np.ceil(LIFE / STEP)), last + 1)


def settling(tau):
    """The relaxation time a droplet of Stokes time `tau` (s) keeps at its terminal speed:
    past Stokes' law (Reynolds numbers over 1, droplets over about 100 um) the drag grows by
    Schiller and Naumann's 1 + 0.15 Re^0.687, so a 400 um droplet falls at 1.6 m/s, not the
    4.8 m/s g tau would give (iterated on the terminal speed)."""
    tau = np.asarray(tau, np.float64)
    diameter = np.sqrt(18.0 * AIR_VISCOSITY * tau / WATER_DENSITY)
    fall = spectrum.GRAVITY * tau
    for _ in range(12):  # damped: the plain iteration oscillates about the balance
        reynolds = fall * diameter * AIR_DENSITY / AIR_VISCOSITY
        fall = 0.5 * (fall + spectrum.GRAVITY * tau / (1.0 + 0.15 * reynolds**0.687))
    return fall / spectrum.GRAVITY


def droplet_sizes(ring):
    """The Stokes times of the points a puff of `ring` is drawn with, as factors of its own:
    SORTED of them from its smallest droplets to its largest in the streaked rings, else one."""
    n = SORTED if ring < STREAKED else 1
    return SIZES ** (np.arange(n) / (n - 1) - 0.5) if n > 1 else np.ones(1)


def droplets(x0, v0, tau, age, wind, spread):
    """Where droplets launched from x0 (n, 3) with velocities v0 (n, 3), relaxation times tau
    (n,), are after `age` (n,) s in the wind (vx, vy): the closed form above, plus the
    turbulence's walk `spread` (n, 3) normal draws times sqrt(2 K age)."""
    w = np.array([wind[0], wind[1], 0.0])
    drift = w + GRAVITY * tau[:, None]
    relax = (tau * -np.expm1(-age / tau))[:, None]
    walk = np.sqrt(2.0 * DIFFUSIVITY * age)[:, None] * spread
    return x0 + drift * age[:, None] + (v0 - drift) * relax + walk


LAUNCHES = residual_foam.Kept(8192)  # each block's launches, by (ring, block, time, wind)
# a ring's launches at a time joined, by (ring, wind, seed, blocks, time): a still camera's
# frames share them, and the blocks' launches are joined once (room for a few views' worth)
GATHERED = residual_foam.Kept(16 * RINGS)


def launches(source, near, k, wind_speed, wind_direction, seed=0, ring=0):
    """For each block (bx, by) of `ring` in `near`, the puffs its sites launch at lattice time
    k: (born (n,), x0 (n, 3), v0 (n, 3), tau (n, sizes), walk (n, 3), start (n,)), when each is
    thrown, from where (above the sea's mean level) and how fast, the settled drag times of
    its droplet_sizes, its turbulent walk's normal draws and its radius then. A site
    launches with the chance of its active whitecap share by the calibration of that time
    (foam.crest_calibration), so a launch never changes with the frame that shows it; it
    throws PER_LAUNCH puffs over the step after, the crest carrying it on meanwhile."""
    when = k * STEP
    ix, iy, xy = _joined([sites(*b, ring) for b in near], axis=-1)
    level, thresholds = foam.crest_calibration(source, when, wind_speed)
    # a site launches if its draw is below its share (at most 1) times the rate, in single
    # precision: the cue is taken only where the draw is below the rate (a gale's rate skips
    # three sites in four)
    draw, rate = noise.uniforms(_salt(seed, ring, 3), ix, iy, k), spray_rate(wind_speed)
    hit = draw < np.float32(rate)
    # from the world's origin: a block's launches are the same whatever blocks join them
    if hit.any():
        cue = source.foam_cue(xy[:, hit], when, np.full(int(hit.sum()), level, np.float32),
                              origin=(0.0, 0.0))
        hit[hit] = draw[hit] < foam.at_thresholds(level, thresholds)(cue) * rate
    block = np.repeat(np.arange(len(near)), BLOCK * BLOCK)[hit]
    at = np.flatnonzero(hit)
    dx, dy, h = surface(source, xy[:, at], when) if at.size else (0.0, 0.0, np.zeros(0))
    water = np.stack([xy[0, at] + dx, xy[1, at] + dy, h], axis=1)
    # each site's puffs
    block, water = np.repeat(block, PER_LAUNCH), np.repeat(water, PER_LAUNCH, axis=0)
    ix, iy = (np.repeat(v[at], PER_LAUNCH) for v in (ix, iy))
    j = np.tile(np.arange(PER_LAUNCH), at.size)
    u = [noise.uniforms(_salt(seed, ring, 10 + c), ix, iy, k, j) for c in range(11)]
    direction = np.array([np.cos(wind_direction), np.sin(wind_direction)])
    crest = CREST_SPEED * phase_speed(source) * direction
    delay = u[0] * STEP
    # thrown from along the crest through the site's cell (across the wind), not one point
    cell = CELL * 2.0**ring
    across, along = (u[9] - 0.5) * cell, (u[10] - 0.5) * 0.5 * cell + crest @ direction * delay
    x0 = water + np.stack([along * direction[0] - across * direction[1],
                           along * direction[1] + across * direction[0],
                           np.zeros_like(delay)], axis=1)
    turn = np.sqrt(-2.0 * np.log1p(-u[1]))  # Box-Muller: normal draws
    v0 = np.stack([crest[0] + TURBULENCE * turn * np.cos(2 * np.pi * u[2]),
                   crest[1] + TURBULENCE * turn * np.sin(2 * np.pi * u[2]),
                   RISE[0] + (RISE[1] - RISE[0]) * u[4]], axis=1)
    # each drawn size's drag time, settled once here rather than every frame that shows it
    tau = settling(TAU[0] * (TAU[1] / TAU[0]) ** u[5][:, None] * droplet_sizes(ring))
    walk = np.sqrt(-2.0 * np.log1p(-u[6]))[:, None] * np.stack(
        [np.cos(2 * np.pi * u[7]), np.sin(2 * np.pi * u[7]),
         VERTICAL * np.abs(np.cos(2 * np.pi * u[8]))], axis=1)
    start = RADIUS[0] + (RADIUS[1] - RADIUS[0]) * u[3]
    puffs = (when + delay, x0, v0, tau, walk, start)
    return [tuple(v[block == b] for v in puffs) for b in range(len(near))]


def spray(source, time, centre, wedge, level, wind_speed, wind_direction, seed=0):
    """The puffs drawn at `time`: (positions (n, 3) float64, radii (n,), opacities (n,) float32), or
    None where the wind tears none: `source` the height source, `centre` the camera's place
    along the sea (x, y), `wedge` its view (view_wedge), `level` the sea's mean level."""
    if spray_rate(wind_speed) <= 0.0:
        return None
    parts = [p for ring in range(RINGS) for p in [_ring(
        source, time, centre, wedge, level, wind_speed, wind_direction, seed, ring)]
        if p is not None]
    if not parts:
        return None
    positions, radii, opacities = _joined(parts)
    return positions, radii.astype(np.float32), opacities.astype(np.float32)


def _joined(parts, axis=0):
    """Each of the parts' arrays, in order, joined across the parts (along `axis`)."""
    return tuple(np.concatenate(v, axis=axis) for v in zip(*parts, strict=True))


def _gathered(source, near, k, wind_speed, wind_direction, seed, ring):
    """The puffs the blocks `near` of `ring` launch at lattice time k, as `launches`' arrays
    joined (an empty tuple: none)."""
    keys = [(ring, bx, by, k, float(wind_speed), float(wind_direction), seed)
            for bx, by in near]
    found = [p for p in LAUNCHES.get(source, keys, lambda missing: launches(
        source, [key[1:3] for key in missing], k, wind_speed, wind_direction, seed, ring))
        if p[0].size]
    return _joined(found) if found else ()


def _ring(source, time, centre, wedge, level, wind_speed, wind_direction, seed, ring):
    """`spray`'s puffs from one ring's sites (None: none)."""
    near = blocks(centre, wedge, ring)
    view = (ring, float(wind_speed), float(wind_direction), seed, near)

    def make(missing):
        return [_gathered(source, near, key[-1], wind_speed, wind_direction, seed, ring)
                for key in missing]
    found = [p for p in GATHERED.get(source, [(*view, k) for k in launch_times(time)], make)
             if p]
    if not found:
        return None
    born, x0, v0, tau, walk, start = _joined(found)
    age = time - born
    weight = ring_weight(np.hypot(x0[:, 0] - centre[0], x0[:, 1] - centre[1]), ring)
    live = np.flatnonzero((age >= 0.0) & (age < LIFE) & (weight > 0.0))
    if not live.size:
        return None
    # each puff's droplets from the smallest to the largest, of its tau's geometric mean
    sizes = droplet_sizes(ring)
    n = len(sizes)
    age, weight, start = (np.repeat(v[live], n) for v in (age, weight, start))
    tau = tau[live].ravel()
    pos = droplets(np.repeat(x0[live], n, axis=0), np.repeat(v0[live], n, axis=0), tau, age,
                   wind_speed * np.array([np.cos(wind_direction), np.sin(wind_direction)]),
                   np.repeat(walk[live], n, axis=0))
    pos[:, 2] += level
    radius = (start + PUFF_GROWTH * np.sqrt(2.0 * DIFFUSIVITY * age)) / np.sqrt(n)
    # a puff's droplets spread over its growing disc: its optical depth falls as it grows
    opacity = (1.0 - age / LIFE) * start / (radius * np.sqrt(n)) * weight
    # of the same mass, droplets d across scatter as 1 / d: the small ones are the spray seen
    opacity *= np.tile(sizes ** -0.25 / sizes[0] ** -0.25, live.size)
    # Sparse spray seen far off would be lone domes of puffs standing on the sea (a far site's
    # launch is 4^ring near ones'): each ring fades by the wind's rate once more, so only a
    # dense spray (rate 1, from force 10) hazes the distance.
    return pos, radius * 2.0**ring, opacity * spray_rate(wind_speed) ** ring


def phase_speed(source):
    """The sea's peak phase speed g / omega_p (m/s): the spectrum's, or the noise's first
    octave's deep-water speed."""
    state = getattr(source, "state", None)
    if state is not None:
        return spectrum.GRAVITY / spectrum.peak_frequency(state)
    return float(np.sqrt(spectrum.GRAVITY * source.wavelength(0) / (2.0 * np.pi)))


def surface(source, xy, when):
    """(dx, dy, h) of the surface at sites `xy` (2, m) at `when`: where their water is."""
    h, d = source.displacement(xy, when, origin=(0.0, 0.0))
    return (0.0, 0.0, h) if d is None else (d[0], d[1], h)
