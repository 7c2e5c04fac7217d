"""What the water shader needs each frame, as plain values (thesis §3.1.3, §3.4.5).

The octaves the grid's band limit left out (band_limit.shader_octaves) come back in the shader
as bump detail: a fractal from the first left-out octave on, at its wavelength, height and time
rate (each height source's `shader_detail`). The sun glint (§3.4.5) needs the direction towards
the sun and whether it is above the horizon.
"""

from dataclasses import dataclass

import numpy as np

# The standard deviation of Blender's noise texture Fac (4D, Detail 2, roughness 0.5), measured
# in an EEVEE render of 400 features: a bump of Distance d moves the surface by 0.072 d (rms).
NOISE_FAC_STD = 0.072


@dataclass(frozen=True)
class Detail:
    """The left-out octaves as the shader's fractal noise: its first octave, frequency (1/m),
    further octaves, roughness, height (m), and its time coordinate per second."""

    first: int
    scale: float
    octaves: float
    roughness: float
    height: float
    time_rate: float


def sun_direction(matrix_world):
    """Unit vector towards a sun lamp of world matrix `matrix_world` (4x4): it shines along its
    local -Z."""
    direction = np.asarray(matrix_world, dtype=np.float64)[:3, 2]
    return direction / max(float(np.linalg.norm(direction)), 1e-12)


def sun_elevation(direction):
    """Degrees above the horizon of a unit direction towards the sun."""
    return float(np.degrees(np.arcsin(np.clip(direction[2], -1.0, 1.0))))


def ripple_reach(proj, width, wavelength, pixels=4.0):
    """How far from a camera (m) a wave `wavelength` long still spans `pixels` pixels across an
    image `width` pixels wide (`proj`: its OpenGL projection): within it the shader shows the
    ripples no geometry holds, fading out over the next doubling of the distance. A perspective
    pixel subtends 2 / (proj[0, 0] width) radians; an orthographic one that many metres, so
    there the reach is all or nothing."""
    proj = np.asarray(proj, dtype=np.float64)
    pixel = 2.0 / (abs(proj[0, 0]) * max(int(width), 1))
    if proj[3, 3] != 0.0:  # orthographic
        return 1e9 if pixel * pixels <= wavelength else 0.0
    return wavelength / (pixels * pixel)
