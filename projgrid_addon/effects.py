"""Which effects a frame calls for, decided from the scene (NumPy only; the bridge gathers facts).

Each effect is AUTO, ON or OFF per ocean. AUTO decides each frame from `SceneFacts`: where the
camera is against the water, which objects in view stand above, below or across the surface,
whether a sun shines from above the horizon, and the wind. Every decision carries the reason the
panel shows. Effects not in `RENDERED` are decided but not drawn yet: they are never listed as
active, and their reason says so.

Foam follows Jensen and Golias (crests) with the whitecap coverage of Monahan and Mac Niocaill
(Fleck Eq. 32) for the wind: the crest threshold is the height exceeded by that share of the sea,
so foam is a function of the frame alone (a farm splitting frames renders the same foam).
"""

from dataclasses import dataclass, field

import numpy as np

from .validation import finite, non_negative

EFFECTS = ("foam", "contact_foam", "underwater", "refraction", "caustics", "godrays",
           "local_reflections", "sun_glint")
MODES = ("AUTO", "ON", "OFF")
RENDERED = frozenset({"foam", "sun_glint"})
# Below this whitecap coverage (wind about 4 m/s, Beaufort 3: "scattered white horses") AUTO
# leaves foam off.
FOAM_MIN_COVERAGE = 5e-4


@dataclass
class SceneObject:
    """An object's world-space bounding box against the view and the water."""

    name: str
    z_min: float
    z_max: float
    in_view: bool


@dataclass
class SceneFacts:
    """What the deciding needs to know about a frame."""

    camera_height: float  # camera z minus the water level (negative: under water)
    bound: float  # the waves' displacement bound (S_upper = level + bound)
    wind_speed: float  # m/s at 10 m
    sun_elevation: float | None  # degrees above the horizon; None: no sun lamp
    objects: list = field(default_factory=list)  # SceneObject


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
    level_hi, level_lo = facts.bound, -facts.bound
    in_view = [o for o in facts.objects if o.in_view]
    crossing = [o for o in in_view if o.z_min < level_hi and o.z_max > level_lo]
    below = [o for o in in_view if o.z_min < level_hi]
    above = [o for o in in_view if o.z_max > level_lo]
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
    elif above:
        reflections = (True, f"{_names(above)} stands above the water in view")
    else:
        reflections = (False, "sky only: nothing stands above the water in view")
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
        "sun_glint": (sun_up, sun_text),
    }


def decide(modes, facts):
    """{effect: (on, reason)} for every effect; `modes` maps effects to AUTO/ON/OFF (default AUTO).

    Only effects in RENDERED can be on; the reason of another says it is not drawn yet.
    """
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
        if on and effect not in RENDERED:
            decisions[effect] = (False, f"needed ({reason}) but not rendered yet")
        else:
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


def foam_threshold(height_field, time, coverage, samples=4096):
    """The height a `coverage` share of the sea exceeds at `time` (crests, Jensen and Golias).

    Estimated on a fixed pattern of points over one tile of the first octave (1024 wavelengths
    square), so it depends on the settings and the time only.
    """
    coverage = min(max(float(coverage), 1e-6), 1.0)
    n = int(np.sqrt(samples))
    k = (np.arange(n) + 0.5) / n
    # A rotated lattice spreads the points over the tile without lining up with the noise grid.
    gx, gy = np.meshgrid(k, k)
    span = 32.0 * height_field.wave_scale
    x = (gx + 0.37 * gy) % 1.0 * span
    y = (gy + 0.61 * gx) % 1.0 * span
    h = height_field.heights(x.ravel(), y.ravel(), time)
    return float(np.quantile(h, 1.0 - coverage))


def foam_amount(heights, threshold, softness):
    """Per-vertex foam in [0, 1]: 0 below `threshold`, rising to 1 over `softness` metres."""
    heights = np.asarray(heights)
    softness = max(float(softness), 1e-9)
    foam = np.subtract(heights, threshold, dtype=np.float32)
    foam *= np.float32(1.0 / softness)
    return np.clip(foam, 0.0, 1.0, out=foam)
