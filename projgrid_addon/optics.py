"""Light in and under the water (NumPy only): absorption per channel with distance, e^(-a d)
(Fleck Eq. 17), and the water body's glow toward the water colour (Eq. 14); caustics, the
refracted-beam intensity of Jensen and Golias (Fleck Eq. 28) per vertex for a receiving depth,
which the Blender layer turns into the water's shadow transparency, and as a tile for the
godrays; and where local reflections are captured (`mirror_capture`): what the camera mirrored
in the water sees."""

import numpy as np

from .daylight import MODEL, sky_light
from .effects import submerged
from .look import DAYLIGHT, OVERCAST_ZENITH, SUN_ELEVATION
from .projected_grid import grid_area, grid_derivative
from .validation import positive

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


def sky_irradiance(strength, overcast, elevation=SUN_ELEVATION, model=MODEL):
    """RGB irradiance our sky world (its Sky Texture's `model`) puts on the sea plane at
    Background Strength `strength` with the sun `elevation` degrees up (None: no sun lamp,
    the sky's default sun), turned `overcast` (0 to 1) toward the overcast: the clear sky's
    (daylight.sky_light) and the overcast's, whose radiance Z (1 + 2 sin h) / 3 (the CIE
    standard overcast sky, Z its zenith's: OVERCAST_ZENITH) integrates over the hemisphere,
    weighed by sin h, to 7 pi / 9 Z."""
    clear = np.asarray(sky_light(SUN_ELEVATION if elevation is None else elevation, model))
    cloud = 7.0 * np.pi / 9.0 * np.asarray(OVERCAST_ZENITH, dtype=np.float64)
    f = min(max(float(overcast), 0.0), 1.0)
    return max(float(strength), 0.0) * (clear + f * (cloud - clear))


def body_light(sun_irradiance, sky_irradiance_, daylight=DAYLIGHT):
    """Per RGB channel, the light on the sea against the daylight the Water Colour is given in:
    (E_sun + E_sky) / D, with E_sun the sun lamp's irradiance on the sea plane, E_sky the
    sky's (`sky_irradiance`) and D the daylight's (RGB each). The water body scatters its
    colour in proportion (its glow, Fleck Eq. 17), as the surface's lit body does."""
    d = np.asarray(daylight, dtype=np.float64)
    sun = np.broadcast_to(np.asarray(sun_irradiance, dtype=np.float64), d.shape)
    return tuple(float(v) for v in (sun + np.asarray(sky_irradiance_, dtype=np.float64)) / d)


# Caustic shadow transparency of flat water; focused light rises to 1 (the most a shadow passes).
CAUSTIC_MEAN = 0.5


def receiving_depth(facts):
    """Depth (m, > 0) the caustics are focused for: the median mid-depth of the submerged parts
    of the objects in view (Jensen and Golias assume one receiving depth); 2 m without any."""
    below = submerged(facts)
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
    area = np.abs(grid_area(qx, qy))
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


GODRAY_TILE_SIZE = 32.0  # metres across the godrays' caustic tile (repeated beyond)


GODRAY_TILE_TEXELS = 256  # texels across it


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
