"""Sea states by the Beaufort scale: the wind, fetch, choppiness and swell of each force.

The wind is the middle of each force's range (WMO), at 10 m. Over open water the sea is fully
developed (Pierson-Moskowitz) up to the height the WMO gives as probable for the force; a
stronger wind rarely blows long enough over a fetch to raise its fully developed sea, so from
force 6 on the fetch is the one whose JONSWAP sea has the WMO's probable height. Choppiness
grows with the force (steeper, sharper crests), and a swell from elsewhere is always running.
"""

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from . import spectrum
from .height_field import HeightField
from .noise import WAVELENGTH
from .validation import finite, integer

# force: (name, wind m/s, WMO probable wave height m, swell height m, swell period s)
BEAUFORT = {
    0: ("Calm", 0.2, 0.0, 0.2, 8.0),
    1: ("Light air", 0.9, 0.1, 0.2, 8.0),
    2: ("Light breeze", 2.5, 0.2, 0.3, 8.0),
    3: ("Gentle breeze", 4.4, 0.6, 0.5, 9.0),
    4: ("Moderate breeze", 6.7, 1.0, 0.5, 9.0),
    5: ("Fresh breeze", 9.4, 2.0, 0.7, 10.0),
    6: ("Strong breeze", 12.3, 3.0, 1.0, 11.0),
    7: ("Near gale", 15.5, 4.0, 1.0, 11.0),
    8: ("Gale", 19.0, 5.5, 1.5, 13.0),
    9: ("Strong gale", 22.6, 7.0, 2.0, 13.0),
    10: ("Storm", 26.5, 9.0, 2.0, 14.0),
}
SWELL_TURN = np.radians(-30.0)  # the swell comes from a little off the wind


@dataclass(frozen=True)
class SeaPreset:
    """What a Beaufort force sets on an ocean (`obj.projgrid`)."""

    name: str
    wind_speed: float
    fetch: float
    choppiness: float
    swell_height: float
    swell_period: float


def sea_state(force, wind_direction=0.0):
    """The preset of Beaufort `force` (0 to 10), the wind blowing toward `wind_direction`."""
    force = integer("beaufort", force, 0, 10)
    name, wind, probable, swell, period = BEAUFORT[force]
    fetch = 0.0
    developed = spectrum.significant_height(spectrum.SeaState(wind_speed=wind))
    if developed > probable > 0.0 and force >= 6:
        fetch = _fetch_for(wind, probable)
    return SeaPreset(name=name, wind_speed=wind, fetch=fetch,
                     choppiness=round(min(1.0, 0.2 + 0.1 * force), 2), swell_height=swell,
                     swell_period=period)


# How much of the sky the Sea State operator clouds over with the force (shaders/sky.weather):
# clear to a fresh breeze, closing over a strong breeze and a near gale, a low overcast from a
# gale on (a look, not the WMO's: its descriptions are of the sea alone).
OVERCAST_FORCES = (5, 8)


def overcast(force):
    """The sky's cloud for Beaufort `force`: 0 up to OVERCAST_FORCES[0], 1 from [1]."""
    return overcast_for_wind(BEAUFORT[integer("beaufort", force, 0, 10)][1])


def overcast_for_wind(wind_speed):
    """The sky's cloud for a wind of `wind_speed` m/s, continuous in it (a keyed storm's sky
    closes as its wind rises, without a step at each force): 0 up to OVERCAST_FORCES[0]'s
    wind, 1 from [1]'s, linear in the wind between; `overcast` at each force's."""
    lo, hi = (BEAUFORT[force][1] for force in OVERCAST_FORCES)
    return min(max((finite("wind_speed", wind_speed) - lo) / (hi - lo), 0.0), 1.0)


# The shortest first octave the noise takes (m): the panel's Wave Scale minimum.
WAVE_SCALE_MIN = 0.01


@lru_cache(maxsize=64)
def noise_waves(wind_speed, fetch=0.0, spectrum_name="JONSWAP", octaves=8, roughness=0.5):
    """(amplitude, wave_scale) of the noise source of `octaves` octaves and `roughness` for
    the wind's sea (m/s at 10 m) over `fetch` (m; 0 fully developed) by `spectrum_name`'s
    spectrum: the same sea as the spectrum's (Horvath 2015), its significant height 4 standard
    deviations of the noise (HeightField.spread) and its peak wavelength the length of the
    first octave's waves (noise.WAVELENGTH lattice periods)."""
    state = spectrum.SeaState(wind_speed=float(wind_speed), fetch=float(fetch),
                              spectrum=spectrum_name)
    sigma = HeightField(amplitude=1.0, octaves=octaves, roughness=roughness,
                        method="exact").spread[0]
    height = spectrum.significant_height(state)
    return (float(height / (4.0 * sigma)) if sigma > 0.0 else 0.0,
            float(max(spectrum.peak_wavelength(state) / WAVELENGTH, WAVE_SCALE_MIN)))


def swell_direction(wind_direction):
    return wind_direction + SWELL_TURN


def _fetch_for(wind, height):
    """The fetch (m) at which the JONSWAP sea of `wind` has significant height `height`."""
    lo, hi = 1e2, spectrum.full_fetch(wind)
    for _ in range(60):  # bisection in log fetch: the height grows with the fetch
        mid = np.sqrt(lo * hi)
        if spectrum.significant_height(spectrum.SeaState(wind_speed=wind, fetch=mid)) < height:
            lo = mid
        else:
            hi = mid
    return float(np.sqrt(lo * hi))
