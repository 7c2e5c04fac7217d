"""Which effects a frame calls for, decided from the scene (NumPy only; the Blender layer gathers
the facts).

Each effect is AUTO, ON or OFF per ocean. AUTO decides each frame from `SceneFacts`: where the
camera is against the water, which objects in view stand above, below or across the surface,
whether a sun shines from above the horizon, and the wind. Every decision carries the reason the
panel shows. The fields of the effects that are on: foam.py (whitecaps, contact foam) and
optics.py (absorption, caustics, godrays, the mirror capture), spray.py.
"""

from dataclasses import dataclass, field

import numpy as np

from .validation import finite, non_negative

EFFECTS = ("foam", "contact_foam", "underwater", "refraction", "caustics", "godrays",
           "local_reflections", "spray", "wakes")
MODES = ("AUTO", "ON", "OFF")
# How far above and below its level AUTO takes the sea to reach (SceneFacts.reach), in standard
# deviations of its heights: the sea's extremes over a shot's view (about 1e5 waves of a
# Gaussian sea exceed 4.4 of them once; 5 leaves a margin for the crests' skew).
REACH_SIGMAS = 5.0
# Below this whitecap coverage (wind about 4 m/s, Beaufort 3: "scattered white horses") AUTO
# leaves foam off.
FOAM_MIN_COVERAGE = 5e-4
# From this speed (m/s) a hull on the water makes a wake AUTO draws (wake_field.py).
MOVING = 0.5
# From this wind AUTO draws spray (spray.py): Beaufort 8's least, where "edges of crests begin
# to break into spindrift" (WMO).
SPRAY_ONSET = 17.2  # m/s


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
    rides: bool = False  # it floats (floating.py): it rises with the waves, none wash up it


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
    # m: the height the sea reaches in a shot, REACH_SIGMAS standard deviations of its heights
    # (at most `bound`, which sums every band's extreme: some 11 of them for the spectrum)
    reach: float = 0.0
    # (name, m/s now, rms m/s over its wake's window) of each hull riding the sea
    movers: tuple = ()

    def key(self):
        """A compact value equal for equal facts, cheap to compare on every update."""
        objects = self.objects_key if self.objects_key is not None else objects_key(self.objects)
        return (self.camera_height, self.bound, self.reach, self.wind_speed,
                self.sun_elevation, self.sun_direction, objects, self.movers)


def objects_key(objects):
    """A compact value equal for equal lists of SceneObjects."""
    boxes = [x.corners for x in objects if x.corners is not None]
    return (tuple(x.name for x in objects),
            np.array([(x.z_min, x.z_max, x.in_view, x.mirrored_in_view, x.rides)
                      for x in objects],
                     dtype=np.float64).tobytes(),
            np.asarray(boxes, dtype=np.float64).tobytes())


def whitecap_coverage(wind_speed, water_minus_air=0.0):
    """Share of the sea covered by whitecaps: 1.59e-5 U^2.55 e^(0.0861 (Tw - Ta)) (Fleck Eq. 32),
    capped at 1."""
    u = non_negative("wind_speed", wind_speed)
    dt = finite("water_minus_air", water_minus_air)
    return float(min(1.0, 1.59e-5 * u**2.55 * np.exp(0.0861 * dt)))


def _names(objects, limit=2):
    return _quoted([o.name for o in objects], limit)


def _quoted(names, limit=2):
    more = len(names) - limit
    return ", ".join(f"'{n}'" for n in names[:limit]) + (f" and {more} more" if more > 0 else "")


def _auto(facts):
    """{effect: (needed, reason)} at AUTO, from the facts sorted once for every effect."""
    crossing = _crossing(facts)
    below = submerged(facts)
    mirrored = [o for o in facts.objects if o.mirrored_in_view and o.z_max > 0.0]
    between = _between(facts)
    under = facts.camera_height < 0.0
    depth = f"camera {abs(facts.camera_height):.3g} m {'below' if under else 'above'} the surface"
    sun = facts.sun_elevation
    sun_up = sun is not None and sun > 0.0
    sun_text = ("no sun lamp" if sun is None else
                f"sun {sun:.0f}° {'above' if sun > 0 else 'below'} the horizon")
    cover = whitecap_coverage(facts.wind_speed)
    spray = facts.wind_speed >= SPRAY_ONSET
    reach = f"the waves' reach ±{facts.reach:.2g} m ({REACH_SIGMAS:g} σ of their height)"
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
    moving = [name for name, _, rms in facts.movers if rms >= MOVING]
    fastest = max((now for _, now, _ in facts.movers), default=0.0)
    if not moving:
        wakes = (False, f"nothing on the water moves faster than {MOVING:g} m/s")
    elif fastest >= MOVING:
        wakes = (True, f"{_quoted(moving)} moves on the water (fastest now {fastest:.2g} m/s)")
    else:
        wakes = (True, f"{_quoted(moving)} moved on the water: its wake is still there")
    return {
        "wakes": wakes,
        "foam": (cover >= FOAM_MIN_COVERAGE,
                 f"wind {facts.wind_speed:.3g} m/s whitecaps {cover:.2%} of the sea"),
        "contact_foam": ((True, f"{_names(crossing)} crosses the surface in view, {reach}")
                         if crossing else (False, f"nothing in view crosses the surface, {reach}")),
        "underwater": (under, depth),
        "refraction": refraction,
        "caustics": caustics,
        "godrays": (sun_up, f"{depth}, {sun_text}") if under else (False, depth),
        "local_reflections": reflections,
        "spray": (spray, f"wind {facts.wind_speed:.3g} m/s tears "
                  f"{'spindrift' if spray else 'no spray'} off the crests (from "
                  f"{SPRAY_ONSET:g} m/s, Beaufort 8)"),
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


def _between(facts):
    """Objects wholly under the water between the mirror capture (optics.mirror_capture) and
    the water it is seen through: in the capture they stand in front of what the water mirrors.
    Mirrored, such a point lies between the camera and the water it sees."""
    if facts.camera_height <= 0.0:
        return []
    return [o for o in facts.objects
            if o.mirrored_in_view and -facts.camera_height < o.z_max <= 0.0]


def _between_text(facts, between):
    return (f"{_names(between)} would show in the reflection (under the water, shallower than "
            f"the camera's {facts.camera_height:.3g} m, in front of the mirror image)")


def submerged(facts):
    """The objects in view reaching below the sea's crests (SceneFacts.reach)."""
    return [o for o in facts.objects if o.in_view and o.z_min < facts.reach]


def _crossing(facts):
    """The objects in view within the waves' reach of the surface, from below it to above,
    that stand in the waves (a float rides them: no contact foam)."""
    return [o for o in submerged(facts) if o.z_max > -facts.reach and not o.rides]


def crossing_boxes(facts):
    """(M, 8, 3) corners of the objects in view that cross the surface (for contact foam)."""
    boxes = [o.corners for o in _crossing(facts) if o.corners is not None]
    return np.array(boxes, dtype=np.float64).reshape(-1, 8, 3)




