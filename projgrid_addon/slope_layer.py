"""The layer between geometry and pixel (Bruneton, Neyret and Holzschuch, *Real-time Realistic
Ocean Lighting using Seamless Transitions from Geometry to BRDF*, 2010, §4: geometry, then
normals, then the BRDF): the slopes of the spectral bands whose waves the grid's vertices drop
long before a pixel stops showing them, as normal maps the shader draws.

Without it, between the vertices' band limit and the pixel's footprint, the waves of the bands
from LAYER_FIRST on (18 m and shorter) were drawn by neither: their slopes were roughness, and
the sun's glitter path at mid distance was a smooth glow with no sparkle.

Each band has one tile of its own (LAYER_TEXELS square, its shortest wave SAMPLES_PER_WAVE
samples, turned by its own angle, with phases of its own), independent of the geometry's tiles
of that band: where the vertices hold a band with weight g the layer draws it with
sqrt(1 - g^2), so the slope variance stays the band's through the hand-over; and where the
pixel outgrows the band's waves the layer keeps the share of its slopes still longer than the
footprint, the rest being roughness (`water_model.layer_gain`, `shading.Filtering`).
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .cascade import (
    BANDS,
    LAYER_FIRST,
    SAMPLES_PER_WAVE,
    Cascade,
    band_level,
    bands,
    tile_phases,
)
from .tiles import turned_texel

LAYER_TEXELS = 128
LAYER_TILE = 100  # the phases' tile index: no geometry tile's
SLOPES = (3, 4)  # spectral_field.FIELDS: the height's slopes along x and y


@dataclass(frozen=True)
class LayerBand:
    """A band of the layer for the shader: the band limit from which the vertices start to hold
    it (whole one level up), and ln of its longest and shortest waves (m)."""

    level: float
    top_log: float
    bottom_log: float


class SlopeLayer:
    """The layer's tiles for a sea state and seed: `slopes(t)` per band, `lookups` for the
    shader's texture coordinates, `bands` for its weights."""

    def __init__(self, state, seed, keyed=False):
        """`keyed`: a keyed wind's (Cascade)."""
        self._made = None
        self.cascades = []
        for b in range(LAYER_FIRST, BANDS):
            shortest, longest = bands()[b]
            self.cascades.append(Cascade(
                LAYER_TEXELS * shortest / SAMPLES_PER_WAVE, np.radians(31.0 + 47.0 * b),
                shortest, longest, 1.0, state, tile_phases(seed, b, LAYER_TILE, LAYER_TEXELS),
                LAYER_TEXELS, keyed=keyed))

    @cached_property
    def bands(self):
        return [LayerBand(band_level(shortest), float(np.log(longest)), float(np.log(shortest)))
                for shortest, longest in bands()[LAYER_FIRST:]]

    def slopes(self, t):
        """Per band, (2, LAYER_TEXELS, LAYER_TEXELS) float32: the slope of the height along
        world x and y at time t, row y, column x of the band's turned tile (made once per
        time: a camera moving over a still frame reuses them)."""
        if self._made is None or self._made[0] != t:
            self._made = (t, [c.samples(t, 0.0, SLOPES) for c in self.cascades])
        return self._made[1]

    def lookups(self, origin):
        """Per band, (a, b, c): a point P on the sea is at texel coordinates
        (a.(P - origin) + c[0], b.(P - origin) + c[1]) of the band's tile (texel (i, j) at
        (i, j), the tile LAYER_TEXELS across), `origin` (x, y) near the camera so the
        shader's single precision is spent near it."""
        out = []
        for c in self.cascades:
            scale = c.texels / c.size
            cos, sin = c.turn[0] * scale, c.turn[1] * scale
            out.append(((cos, sin, 0.0), (-sin, cos, 0.0),
                        turned_texel(origin, c.turn, scale, c.texels)))
        return out

    def slope_variance(self):
        """Per band, the slope variance its tile holds: each wave vector's |k|^2 times its
        mean power (Parseval)."""
        return [float(np.sum((c.kx**2 + c.ky**2) * c.half_power())) for c in self.cascades]
