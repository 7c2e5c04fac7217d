"""Whitecaps on the dominant waves' crests (spectral_field.SpectralField.foam_cue): they break at
the crests of a group's highest waves (Donelan, Longuet-Higgins and Turner 1972), not on a
swell's (swells do not break)."""

import numpy as np
import pytest

from projgrid_addon import effects, foam, sea_states
from projgrid_addon.cascade import EVERY_BAND, GEOMETRY
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


@pytest.mark.parametrize("force", [5, 8, 10])
def test_whitecaps_sit_on_the_wind_sea_s_crests_not_the_swell_s(force):
    """Over four of the crest sum's longest waves each way, the share of the sea Monahan's
    coverage gives with the highest cue: the wind sea's height there (the crest sum's) is at
    least 1.5 of its standard deviations up (a crest of the highest waves is about 2; without
    the crests' steepness in the cue, a storm's foam averaged 1.3 at force 10), and the rest
    of the sea's (the swell's core and longer bands) within 0.2 of its own of its mean."""
    p = sea_states.sea_state(force)
    state = SeaState(wind_speed=p.wind_speed, fetch=p.fetch, swell_height=p.swell_height,
                     swell_period=p.swell_period, swell_direction=sea_states.SWELL_TURN)
    sea = SpectralField(state, p.choppiness, seed=3)
    k = (np.arange(300) + 0.5) / 300 * 4.0 * sea.crest_longest
    xy = np.stack(np.meshgrid(k, k))
    level = foam.whitecap_level(sea)
    lod = np.full(xy.shape[1:], level, np.float32)
    wind = sea.sample(xy, 10.0, lod, GEOMETRY, crest=EVERY_BAND)[1][0]
    swell = sea.sample(xy, 10.0, lod, (0,))[0] - wind
    cue = foam.crest_cue(sea, xy, 10.0, lod)
    white = cue > np.quantile(cue, 1.0 - effects.whitecap_coverage(p.wind_speed))
    assert wind[white].mean() > 1.5 * wind.std()
    assert abs(swell[white].mean() - swell.mean()) < 0.2 * swell.std()
