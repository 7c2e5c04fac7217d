"""Which effects a frame calls for, decided from the scene (NumPy only; the bridge gathers facts).

Each effect is AUTO, ON or OFF per ocean. AUTO decides each frame from `SceneFacts`: where the
camera is against the water, which objects in view stand above, below or across the surface,
whether a sun shines from above the horizon, and the wind. Every decision carries the reason the
panel shows.

Foam follows Jensen and Golias (crests) with the whitecap coverage of Monahan and Mac Niocaill
(Fleck Eq. 32) for the wind: the crest threshold is the height exceeded by that share of the sea,
so foam is a function of the frame alone (a farm splitting frames renders the same foam).
Contact foam rings the objects that cross the surface. Caustics are the refracted-beam intensity
of Jensen and Golias (Fleck Eq. 28) per vertex, for a receiving depth; the bridge turns them into
the water's shadow transparency, so the scene's sun projects them onto whatever lies below.
Under water, light is absorbed per channel with distance, e^(-a d) (Fleck Eq. 17), and scattered
toward the water colour (Eq. 14). Local reflections are what the camera mirrored in the water
sees (`mirror_capture`).

Over 300 lines on purpose: the decisions (`decide`) and the fields they turn on share
SceneFacts and the constants each decision's reason quotes; split, each half would import the
other's.
"""

import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from .projected_grid import grid_derivative
from .validation import finite, non_negative, positive

EFFECTS = ("foam", "contact_foam", "underwater", "refraction", "caustics", "godrays",
           "local_reflections")
MODES = ("AUTO", "ON", "OFF")
# Below this whitecap coverage (wind about 4 m/s, Beaufort 3: "scattered white horses") AUTO
# leaves foam off.
FOAM_MIN_COVERAGE = 5e-4
# Added to a whitecap threshold where the sea has no wave to foam: out of any cue's reach.
NO_FOAM = 1e6
FOAM_PERIOD = 1.0  # seconds between the foam's calibrations (foam_thresholds)
FOAM_SOFTNESS = 1.0  # a whitecap's ramp at full detail, in the cue's standard deviations
# A linear ramp this many standard deviations wide has the slope of the normal distribution's
# CDF at its middle (sqrt(2 pi)): the share of a vertex that the waves it leaves out foam.
UNRESOLVED_RAMP = 2.5
# m: waves longer than this make whitecaps a vertex should place; the foam of shorter ones is
# the shader's grain (as the shader's WHITECAP: beyond it a pixel shows the mean cover).
WHITECAP_WAVE = 8.0
# Absorption a (1/m) per RGB channel of clear coastal sea water (Fleck Eq. 17): red light is
# gone after a few metres, blue travels tens.
ABSORPTION = (0.45, 0.09, 0.06)
# The water's clarity: the distance (m) over which its clearest channel keeps 1/e of its light.
CLARITY = 1.0 / min(ABSORPTION)


def absorption(clarity):
    """Absorption per metre per RGB channel of water whose clearest channel keeps 1/e of its
    light over `clarity` metres: clear coastal water's (ABSORPTION), scaled."""
    clarity = positive("clarity", clarity)
    return tuple(a * CLARITY / clarity for a in ABSORPTION)


def body_light(sun_irradiance, sky_strength, daylight, daylight_sun):
    """Per RGB channel, the light on the sea against the daylight the Water Colour is given in:
    (E_sun + s (D - D_sun)) / D, with E_sun the sun lamp's irradiance on the sea plane (RGB),
    s the sky's strength against the daylight's sky, D the daylight's irradiance (RGB) and
    D_sun its sun's. The water body scatters its colour in proportion (its glow, Fleck Eq.
    17), as the surface's lit body does."""
    d = np.asarray(daylight, dtype=np.float64)
    sun = np.broadcast_to(np.asarray(sun_irradiance, dtype=np.float64), d.shape)
    return tuple(float(v) for v in (sun + max(float(sky_strength), 0.0) * (d - daylight_sun))
                 / d)


# Caustic shadow transparency of flat water; focused light rises to 1 (the most a shadow passes).
CAUSTIC_MEAN = 0.5


@dataclass
class SceneObject:
    """An object's bounding box against the view and the water: heights relative to the water
    level, corners in world space."""

    name: str
    z_min: float
    z_max: float
    in_view: bool
    corners: np.ndarray | None = None  # (8, 3) world box corners in Blender's bound_box order
    mirrored_in_view: bool = False  # its mirror image in the water plane may be in view


@dataclass
class SceneFacts:
    """What the deciding needs to know about a frame."""

    camera_height: float  # camera z minus the water level (negative: under water)
    bound: float  # the waves' displacement bound (S_upper = level + bound)
    wind_speed: float  # m/s at 10 m
    sun_elevation: float | None  # degrees above the horizon; None: no sun lamp
    objects: list = field(default_factory=list)  # SceneObject
    sun_direction: tuple | None = None  # unit vector towards the sun
    objects_key: tuple | None = None  # objects_key(objects), when the caller keeps it

    def key(self):
        """A compact value equal for equal facts, cheap to compare on every update."""
        objects = self.objects_key if self.objects_key is not None else objects_key(self.objects)
        return (self.camera_height, self.bound, self.wind_speed, self.sun_elevation,
                self.sun_direction, objects)


def objects_key(objects):
    """A compact value equal for equal lists of SceneObjects."""
    boxes = [x.corners for x in objects if x.corners is not None]
    return (tuple(x.name for x in objects),
            np.array([(x.z_min, x.z_max, x.in_view, x.mirrored_in_view) for x in objects],
                     dtype=np.float64).tobytes(),
            np.asarray(boxes, dtype=np.float64).tobytes())


def whitecap_coverage(wind_speed, water_minus_air=0.0):
    """Share of the sea covered by whitecaps: 1.59e-5 U^2.55 e^(0.0861 (Tw - Ta)) (Fleck Eq. 32),
    capped at 1."""
    u = non_negative("wind_speed", wind_speed)
    dt = finite("water_minus_air", water_minus_air)
    return float(min(1.0, 1.59e-5 * u**2.55 * np.exp(0.0861 * dt)))


def _names(objects, limit=2):
    names = [f"'{o.name}'" for o in objects[:limit]]
    more = len(objects) - limit
    return ", ".join(names) + (f" and {more} more" if more > 0 else "")


def _auto(facts):
    """{effect: (needed, reason)} at AUTO, from the facts sorted once for every effect."""
    crossing = _crossing(facts)
    below = _submerged(facts)
    mirrored = [o for o in facts.objects if o.mirrored_in_view and o.z_max > 0.0]
    between = _between(facts)
    under = facts.camera_height < 0.0
    depth = f"camera {abs(facts.camera_height):.3g} m {'below' if under else 'above'} the surface"
    sun = facts.sun_elevation
    sun_up = sun is not None and sun > 0.0
    sun_text = ("no sun lamp" if sun is None else
                f"sun {sun:.0f}° {'above' if sun > 0 else 'below'} the horizon")
    cover = whitecap_coverage(facts.wind_speed)
    below_text = f"{_names(below)} is below the surface in view"

    if under:
        refraction = (False, f"{depth} (the underwater view shows what is below)")
    elif below:
        refraction = (True, below_text)
    else:
        refraction = (False, "nothing in view is below the surface")
    if not sun_up:
        caustics = (False, sun_text)
    elif below:
        caustics = (True, f"{sun_text}, {below_text}")
    else:
        caustics = (False, "nothing in view is below the surface to receive them")
    if under:
        reflections = (False, depth)
    elif mirrored and between:
        reflections = (False, _between_text(facts, between))
    elif mirrored:
        reflections = (True, f"{_names(mirrored)} stands above the water, mirrored in view")
    else:
        reflections = (False, "sky only: nothing above the water is mirrored in view")
    return {
        "foam": (cover >= FOAM_MIN_COVERAGE,
                 f"wind {facts.wind_speed:.3g} m/s whitecaps {cover:.2%} of the sea"),
        "contact_foam": ((True, f"{_names(crossing)} crosses the surface in view") if crossing
                         else (False, "nothing in view crosses the surface")),
        "underwater": (under, depth),
        "refraction": refraction,
        "caustics": caustics,
        "godrays": (sun_up, f"{depth}, {sun_text}") if under else (False, depth),
        "local_reflections": reflections,
    }


def decide(modes, facts):
    """{effect: (on, reason)} for every effect; `modes` maps effects to AUTO, ON or OFF (AUTO
    when missing)."""
    decisions = {}
    auto = None
    for effect in EFFECTS:
        mode = modes.get(effect, "AUTO")
        if mode not in MODES:
            raise ValueError(f"{effect}: mode must be one of {MODES}, got {mode!r}")
        if mode == "OFF":
            on, reason = False, "switched off"
        elif mode == "ON":
            on, reason = True, "switched on"
        else:
            auto = auto or _auto(facts)
            on, reason = auto[effect]
        if mode == "ON" and effect == "local_reflections" and (between := _between(facts)):
            reason = f"{reason}, but {_between_text(facts, between)}"
        decisions[effect] = (on, reason)
    return decisions


def boxes_in_view(camera, corners):
    """Which boxes, given by their (M, 8, 3) world corners, may intersect the view frustum.

    A box is out when all its corners lie outside one frustum plane (conservative: a box near a
    frustum edge can be kept though it misses the frustum).
    """
    corners = np.asarray(corners, dtype=np.float64).reshape(-1, 8, 3)
    c = camera.clip(corners)  # (M, 8, 4)
    x, y, z, w = np.moveaxis(c, -1, 0)
    outside = np.stack([x < -w, x > w, y < -w, y > w, z < -w, z > w])  # (6, M, 8)
    return ~outside.all(axis=2).any(axis=0)


def sea_sample(span, samples=4096):
    """x, y of a fixed pattern of `samples` points over a square `span` metres across: a
    rotated lattice, which spreads them over the square without lining up with a texture."""
    n = int(np.sqrt(samples))
    k = (np.arange(n) + 0.5) / n
    gx, gy = np.meshgrid(k, k)
    return ((gx + 0.37 * gy) % 1.0 * span).ravel(), ((gy + 0.61 * gx) % 1.0 * span).ravel()


def foam_thresholds(source, time, coverage, samples=16384):
    """Whitecap thresholds of a height source's foam cue (its `foam_cue`: the height for the
    noise, how far the choppy surface folds for the spectrum), at each of its band limits
    (`foam_levels`): on a fixed pattern of sea points, the mean foam is `coverage` at the
    band limit they are evaluated with, so a vertex's foam covers the wind's share of the sea
    whatever detail its geometry holds (Jensen and Golias put foam where the surface is high
    or folds; Monahan and Mac Niocaill give how much). Returns (levels, thresholds, widths):
    each the width of the ramp the foam rises over (`whitecaps`).

    The sources' statistics drift with time (the noise's octaves move through their lattices;
    the spectrum's tiles hold finitely many waves, whose rare folds come and go: one threshold
    for all times let the cover drift between 0.55 and 1.6 times the coverage). So it is
    calibrated every FOAM_PERIOD seconds and interpolated between, and a frame is a function of
    the settings and its time alone: a farm splitting frames renders the same foam."""
    coverage = min(max(float(coverage), 1e-6), 1.0)
    t0 = float(np.floor(time / FOAM_PERIOD) * FOAM_PERIOD)
    a, b = (_calibration(source, t, coverage, samples) for t in (t0, t0 + FOAM_PERIOD))
    source.prepare(time)  # a calibration prepares it at its own time: back to the frame's
    f = (time - t0) / FOAM_PERIOD
    return a[0], (1.0 - f) * a[1] + f * b[1], (1.0 - f) * a[2] + f * b[2]


FOAM_KEPT = 4  # calibrations a source keeps (the frame's two and two ahead)
_AHEAD = {"pool": None, "pending": {}}
_AHEAD_LOCK = threading.Lock()


def calibrate_ahead(source, time, coverage, samples=16384):
    """Start the whitecap calibrations of the next two FOAM_PERIODs after `time` on a worker
    thread, so that playing a sequence does not stall each time a period begins (a spectral
    calibration costs ten frames). What the worker makes is what `foam_thresholds` would
    (the same function of the settings and the time, on the source's `twin`), put into the
    source's own cache; a frame that needs one still being made waits for it. Returns the
    number of calibrations started (0 for a source with no `twin`)."""
    twin = getattr(source, "twin", None)
    if twin is None:
        return 0
    coverage = min(max(float(coverage), 1e-6), 1.0)
    cache = source.__dict__.setdefault("_foam_calibrations", {})
    t0 = float(np.floor(time / FOAM_PERIOD) * FOAM_PERIOD)
    started = 0
    with _AHEAD_LOCK:
        for t in (t0 + FOAM_PERIOD, t0 + 2.0 * FOAM_PERIOD):
            key = (t, coverage, samples)
            if key in cache or (id(cache), key) in _AHEAD["pending"]:
                continue
            if _AHEAD["pool"] is None:
                _AHEAD["pool"] = ThreadPoolExecutor(1, thread_name_prefix="projgrid-foam")
            _AHEAD["pending"][id(cache), key] = _AHEAD["pool"].submit(
                _calibrate_into, twin(), cache, key)
            started += 1
    return started


def finish_ahead():
    """Wait for the calibrations being made ahead: before Blender runs long native work (a
    render, the bake's export) with no thread of ours beside it (one beside the USD export
    crashed Blender 4.5 in its exporter)."""
    with _AHEAD_LOCK:
        pending = list(_AHEAD["pending"].values())
    for job in pending:
        job.exception()  # waits; a worker's error is the frame's to meet, not this one's


def _calibrate_into(source, cache, key):
    try:
        return _calibration(source, *key, cache=cache)
    finally:
        with _AHEAD_LOCK:
            _AHEAD["pending"].pop((id(cache), key), None)


def _calibration(source, time, coverage, samples, cache=None):
    if cache is None:
        cache = source.__dict__.setdefault("_foam_calibrations", {})
    key = (time, coverage, samples)
    with _AHEAD_LOCK:
        pending = _AHEAD["pending"].get((id(cache), key))
    if pending is not None and threading.current_thread() is threading.main_thread():
        pending.result()  # being made ahead: wait rather than make it twice
    made = cache.get(key)
    if made is None:
        x, y = sea_sample(source.foam_span, samples)
        xy = np.stack([x, y])
        levels = np.asarray(source.foam_levels(), dtype=np.float64)
        cues = [source.foam_cue(xy, time, np.full(x.shape, level, np.float32))
                for level in levels]
        spreads = np.array([float(cue.std()) for cue in cues])
        placed = np.clip(source.whole_level(WHITECAP_WAVE), levels[0], levels[-1])
        whole = float(np.interp(placed, levels, spreads))
        widths = _ramp_widths(spreads, whole)
        thresholds = []
        for cue, spread, width in zip(cues, spreads, widths, strict=True):
            # no wave here, nor any whitecap-long (WHITECAP_WAVE) for the ramp to stand for:
            # no foam (a light air's, whose share is below FOAM_MIN_COVERAGE anyway)
            if max(spread, whole) <= 1e-9 * (1.0 + float(np.abs(cue).max())):
                thresholds.append(float(cue.max()) + NO_FOAM)
            else:  # the threshold whose foam, ramp and all, covers `coverage` of the pattern
                thresholds.append(_covering(cue, coverage, width))
        made = (levels, np.array(thresholds), widths)
        with _AHEAD_LOCK:
            cache[key] = made
            for old in list(cache)[:-FOAM_KEPT]:  # the oldest made first
                del cache[old]
    return made


def _ramp_widths(spreads, placed):
    """The width of each level's foam ramp: FOAM_SOFTNESS of the cue's spread there, widened
    by the spread of the waves longer than WHITECAP_WAVE the level leaves out (`placed`, the
    cue's spread with them whole, less the level's own, the two independent), so a vertex
    holding only the long waves gets the share of its area the shorter ones would foam,
    rising smoothly on the long waves' crests, not a whole whitecap along each long crest."""
    unresolved = np.sqrt(np.maximum(placed * placed - spreads * spreads, 0.0))
    widths = np.hypot(FOAM_SOFTNESS * spreads, UNRESOLVED_RAMP * unresolved)
    return np.where(widths > 0.0, widths, 1.0)


def _covering(cue, coverage, width):
    """The threshold at which the mean of `whitecaps` over the sample `cue` is `coverage`."""
    lo, hi = float(cue.min()) - width, float(cue.max()) + width
    for _ in range(40):  # bisection: the mean foam falls as the threshold rises
        mid = 0.5 * (lo + hi)
        if np.clip((cue - mid) / width + 0.5, 0.0, 1.0).mean() > coverage:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def whitecaps(cue, lod, calibration):
    """Per-vertex foam in [0, 1], the share of the sea there whitecaps cover, from the cue at
    the vertices and `foam_thresholds`: rising from 0 to 1 across the vertex's threshold over
    the ramp's width, centred on it, so the mean foam over the sea is the coverage. `lod`
    None: every band, whole."""
    levels, thresholds, widths = calibration
    cue = np.asarray(cue, dtype=np.float32).ravel()
    if lod is None:
        t, width = thresholds[-1], widths[-1]
    else:
        lod = np.asarray(lod, dtype=np.float64).ravel()
        t, width = np.interp(lod, levels, thresholds), np.interp(lod, levels, widths)
    foam = np.subtract(cue, t, dtype=np.float32)
    foam /= np.asarray(width, dtype=np.float32)
    foam += np.float32(0.5)
    return np.clip(foam, 0.0, 1.0, out=foam)


def _between(facts):
    """Objects wholly under the water between the mirror capture (effects.mirror_capture) and
    the water it is seen through: in the capture they stand in front of what the water mirrors.
    Mirrored, such a point lies between the camera and the water it sees."""
    if facts.camera_height <= 0.0:
        return []
    return [o for o in facts.objects
            if o.mirrored_in_view and -facts.camera_height < o.z_max <= 0.0]


def _between_text(facts, between):
    return (f"{_names(between)} would show in the reflection (under the water, shallower than "
            f"the camera's {facts.camera_height:.3g} m, in front of the mirror image)")


def _submerged(facts):
    return [o for o in facts.objects if o.in_view and o.z_min < facts.bound]


def _crossing(facts):
    """The objects in view within the waves' reach of the surface, from below it to above."""
    return [o for o in _submerged(facts) if o.z_max > -facts.bound]


def crossing_boxes(facts):
    """(M, 8, 3) corners of the objects in view that cross the surface (for contact foam)."""
    boxes = [o.corners for o in _crossing(facts) if o.corners is not None]
    return np.array(boxes, dtype=np.float64).reshape(-1, 8, 3)


def contact_foam(x, y, z, boxes, width):
    """Per-vertex foam in [0, 1] around boxes crossing the water: 1 at a box, fading to 0 at
    `width` metres from it. Points and box corners are world space relative to one origin.

    The distance is to the box itself, in its own frame: Blender's bound_box corners 0, 4, 3, 1
    are its origin and its x, y, z edges, which stay orthogonal under rotation and scale.
    """
    width = max(float(width), 1e-6)
    p = np.stack([np.ravel(x), np.ravel(y), np.ravel(z)], axis=-1)
    foam = np.zeros(len(p), dtype=np.float32)
    for corners in np.asarray(boxes, dtype=np.float64).reshape(-1, 8, 3):
        # Only the points within `width` of the box's extent in x and y can get any.
        lo, hi = corners[:, :2].min(axis=0) - width, corners[:, :2].max(axis=0) + width
        near_box = np.flatnonzero((p[:, 0] >= lo[0]) & (p[:, 0] <= hi[0])
                                  & (p[:, 1] >= lo[1]) & (p[:, 1] <= hi[1]))
        if near_box.size == 0:
            continue
        q = p[near_box]
        origin = corners[0]
        edges = corners[[4, 3, 1]] - origin  # (3, 3)
        length2 = np.einsum("ij,ij->i", edges, edges)
        t = (q - origin) @ edges.T / np.where(length2 > 0.0, length2, 1.0)
        nearest = origin + np.clip(t, 0.0, 1.0) @ edges
        near = np.clip(1.0 - np.linalg.norm(q - nearest, axis=-1) / width, 0.0, 1.0)
        foam[near_box] = np.maximum(foam[near_box], near * near)
    return foam


def receiving_depth(facts):
    """Depth (m, > 0) the caustics are focused for: the median mid-depth of the submerged parts
    of the objects in view (Jensen and Golias assume one receiving depth); 2 m without any."""
    below = _submerged(facts)
    if not below:
        return 2.0
    mid = [-(o.z_min + min(o.z_max, 0.0)) / 2.0 for o in below]
    return float(max(np.median(mid), 0.1))


def caustic_intensity(surface, sun_direction, depth, ior=1.333):
    """Per-vertex caustic intensity relative to flat water (Fleck Eq. 28, Jensen and Golias).

    Each vertex's sun ray is refracted at the surface and carried to the plane `depth` metres
    below the water level; the intensity is the sun's flux through the surface element,
    L.(dP/du x dP/dv), over the area the refracted beam covers there, divided by L_z (what flat
    water gives). `surface` is GridResult.surface: (x, y, height above level), (ny, nx) arrays.
    """
    x, y, h = surface
    sun = np.asarray(sun_direction, dtype=np.float64)
    sun = sun / np.linalg.norm(sun)
    if sun[2] <= 0.0:
        return np.zeros(x.size, dtype=np.float32)
    d = grid_derivative
    xu, yu, hu, xv, yv, hv = d(x, 1), d(y, 1), d(h, 1), d(x, 0), d(y, 0), d(h, 0)
    # dP/du x dP/dv, whose z (the flat grid's area) is positive: the grid is counter-clockwise.
    c = (yu * hv - hu * yv, hu * xv - xu * hv, xu * yv - yu * xv)
    flux = sun[0] * c[0] + sun[1] * c[1] + sun[2] * c[2]
    length = np.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
    tx, ty, tz = _refract(sun, c, length, flux / length, 1.0 / ior)
    s = (h + depth) / np.maximum(-tz, 1e-6)
    qx = x + s * tx
    qy = y + s * ty
    area = np.abs(d(qx, 1) * d(qy, 0) - d(qy, 1) * d(qx, 0))
    ratio = np.divide(flux, area * sun[2], out=np.ones_like(flux), where=area > 0.0)
    return ratio.astype(np.float32).ravel()


def caustic_shadow(intensity):
    """The water's shadow transparency in [0, 1] from caustic intensities: CAUSTIC_MEAN for flat
    water, 1 where the light is focused twice as much or more."""
    return np.clip(np.asarray(intensity, dtype=np.float32) * np.float32(CAUSTIC_MEAN), 0.0, 1.0)


def mirror_capture(eye, level, bound, reach):
    """Where local reflections are captured: (location, half extents, clip start).

    A flat mirror at `level` shows the eye what the eye mirrored in the plane sees through it:
    the reflected ray at every surface point continues the ray from the mirrored eye. A sphere
    capture there, looked up along the water's reflection vector without parallax, is that
    mirror, bent by the waves' normals. It is clipped at the plane (nothing nearer than the eye's
    height), and its influence is a slab from the mirrored eye to the crests, `reach` metres
    each way, so glossy objects above the waves keep their own reflections.
    """
    eye = np.asarray(eye, dtype=np.float64)
    height = abs(float(eye[2]) - level)
    location = (float(eye[0]), float(eye[1]), 2.0 * level - float(eye[2]))
    reach = max(float(reach), 1e-3)
    return location, (reach, reach, height + max(float(bound), 0.0)), max(height, 1e-3)


def _refract(sun, normal, length, cos, eta):
    """Snell's law (Fleck §2.1.2): the direction, as three components, of the sun's ray -L
    refracted into the water through the normal `normal` of length `length`, at cos = L.n/|n|
    (components may be arrays: every vertex at once)."""
    along_n = (eta * cos - np.sqrt(1.0 - eta * eta * (1.0 - cos * cos))) / length
    return tuple(-eta * sun[i] + along_n * normal[i] for i in range(3))


def refracted_sun(sun_direction, ior=1.333):
    """Unit direction of the sun's light under flat water: downward, bent toward the
    vertical."""
    sun = np.asarray(sun_direction, dtype=np.float64)
    sun = sun / np.linalg.norm(sun)
    return np.array(_refract(sun, (0.0, 0.0, 1.0), 1.0, max(float(sun[2]), 0.0), 1.0 / ior))


def caustic_tile(height_field, time, centre, size, n, sun_direction, depth):
    """Caustic intensity (Fleck Eq. 28) on a regular n x n grid of world points `size` metres
    square, rows along y and columns along x as an image's pixels, its lower-left corner at
    `centre` minus half the size. The godrays light the water body with it, looked up along the
    refracted sun (Jensen and Golias light their volume slices with the caustic pattern)."""
    k = (np.arange(n) + 0.5) * (size / n) - 0.5 * size
    x, y = np.meshgrid(centre[0] + k, centre[1] + k)
    h = height_field.heights(x, y, time)
    return caustic_intensity((x, y, h), sun_direction, depth).reshape(n, n)


def tile_lookup(sun_direction, level, corner, size, ior=1.333):
    """(a, b, c): the tile's texture coordinates of a point Q under the water are
    (a.Q + c[0], b.Q + c[1]): Q carried up the refracted sun ray to the water `level`, then
    measured from the tile's lower-left `corner` in units of its `size`."""
    d = refracted_sun(sun_direction, ior)
    sx, sy = d[0] / d[2], d[1] / d[2]
    a = np.array((1.0, 0.0, -sx)) / size
    b = np.array((0.0, 1.0, -sy)) / size
    c = ((sx * level - corner[0]) / size, (sy * level - corner[1]) / size)
    return a, b, c


# ---- The per-vertex and per-frame fields the Blender layer writes (computed only while on) ----

CONTACT_FOAM_REACH = 0.5  # metres of foam around an object, beyond the waves' own height
GODRAY_TILE_SIZE = 32.0  # metres across the godrays' caustic tile (repeated beyond)
GODRAY_TILE_TEXELS = 256  # texels across it


def contact_foam_width(bound):
    """How far contact foam reaches from an object: half a metre plus the waves' bound."""
    return CONTACT_FOAM_REACH + bound


def foam_field(source, result, time, wind_speed, crests, boxes, level, ahead=False):
    """Per-vertex foam of a frame in [0, 1], or None with neither kind on: whitecaps (when
    `crests`) covering the wind's share of the sea (`whitecaps`), and rings around the `boxes`
    crossing the water (contact foam), combined by their maximum. `result` is the frame's
    GridResult: the cue is taken at its grid points before any choppy displacement, and from
    the grid itself where the source asks for it (the spectrum's folding). `ahead`: also
    start the coming seconds' calibrations on a worker (`calibrate_ahead`), for playback."""
    foam = None
    surface = result.surface
    if crests:
        coverage = max(whitecap_coverage(wind_speed), FOAM_MIN_COVERAGE)
        calibration = foam_thresholds(source, time, coverage)
        if ahead:
            calibrate_ahead(source, time, coverage)
        xy = result.base if result.base is not None else np.stack(surface[:2])
        lod = result.lod.reshape(xy.shape[1:])
        foam = whitecaps(source.foam_cue(xy, time, lod, grid=surface[:2]), lod, calibration)
    if len(boxes):
        x, y, h = surface
        ring = contact_foam(x, y, h + level, boxes, contact_foam_width(source.bound))
        foam = ring if foam is None else np.maximum(foam, ring)
    return foam


def caustic_field(surface, facts):
    """Per-vertex caustic shadow transparency minus CAUSTIC_MEAN (Fleck Eq. 28), focused for
    the depth of the submerged objects in view; None without a sun."""
    if facts.sun_direction is None:
        return None
    intensity = caustic_intensity(surface, facts.sun_direction, receiving_depth(facts))
    return caustic_shadow(intensity) - np.float32(CAUSTIC_MEAN)


def godray_field(height_field, time, eye, level, facts):
    """The godrays' caustic tile around the camera and its lookup (`tile_lookup`), or None
    without a sun. Texel-aligned, so the pattern stays put in the world as the camera moves;
    focused at the camera's depth (the light around the eye), clipped at 4 so a focus's
    singular peak does not become a firefly."""
    if facts.sun_direction is None:
        return None
    size, n = GODRAY_TILE_SIZE, GODRAY_TILE_TEXELS
    texel = size / n
    centre = np.round(np.asarray(eye[:2], dtype=np.float64) / texel) * texel
    depth = max(-facts.camera_height, 1.0)
    tile = caustic_tile(height_field, time, centre, size, n, facts.sun_direction, depth)
    np.clip(tile, 0.0, 4.0, out=tile)
    return tile, tile_lookup(facts.sun_direction, level, centre - 0.5 * size, size)
