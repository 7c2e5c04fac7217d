"""The slopes the sea draws against the spectrum's and Cox and Munk's: the ripples, the
filtering's roughness, the gusts, the slope layer and the glint's facets."""

import numpy as np
import pytest
from look_numpy import NUMPY, footprint_log, group_inputs

from projgrid_addon import (
    HeightField,
    band_limit,
    shading,
    slope_layer,
    spectrum,
    water_model,
)
from projgrid_addon.camera import orthographic, perspective
from projgrid_addon.cascade import BANDS, LAYER_FIRST, band_level, band_shares, bands
from projgrid_addon.look import GUST_FAC_STD, GUST_SCALE
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import GRAVITY, SeaState, integrate


def drawn_slope(detail):
    """The slope variance the bump of a Detail of Blender's noise (Detail 2) draws: its
    height's spread times 2π scale / 1.223, the noise's waves being 1.223 of its cells long."""
    return (detail.height * shading.NOISE_FAC_STD * 2.0 * np.pi * detail.scale / 1.223)**2


def test_the_ripples_are_the_spectrum_s_tail():
    """The waves shorter than the last band come back as shading detail drawing the
    spectrum's slopes there, which the filtering books as drawn: Pierson-Moskowitz's k⁻⁴
    tail, α/2 ln(k₂/k₁) with α = 0.0081, whatever the wind (its saturation range). Blender's
    noise of Detail 2 draws waves NOISE_WAVES (1.22) of its cells long, so its slope is its
    height's spread times 2π scale / 1.22 (as high as the spectrum's own, σ² = α/4 (1/k₁² −
    1/k₂²), it drew a sixth of that)."""
    k1 = 2.0 * np.pi / bands()[-1][0]
    k2 = k1 * 2.0**shading.RIPPLE_OCTAVES
    for u in (5.0, 15.0):
        source = SpectralField(SeaState(wind_speed=u))
        detail, longest = source.ripple()
        assert 1.0 / detail.scale == pytest.approx(longest) and detail.octaves == 2.0
        drawn = drawn_slope(detail)
        assert drawn == pytest.approx(0.0081 / 2.0 * np.log(k2 / k1), rel=0.03)
        assert drawn == pytest.approx(source.slopes.ripple, rel=1e-6)


def test_the_noise_s_ripples_carry_on_its_fractal():
    """The noise's ripples are its next octaves (at roughness 0.5, each half the one before):
    as steep as the octaves a noise of three more would add (the per-octave keys are the
    same), which Blender's noise draws (shading.detail_height) within 15 % as high (its waves
    are a little longer than ours); a noise without octaves has none, so a flat sea stays flat and
    the wind's slopes are all roughness."""
    source = HeightField(amplitude=0.8, wave_scale=30.0, octaves=6, method="exact", seed=3)
    more = HeightField(amplitude=0.8, wave_scale=30.0, method="exact", seed=3,
                       octaves=6 + shading.RIPPLE_OCTAVES)
    detail, longest = source.ripple()
    assert longest == pytest.approx(30.0 / 2**6) and 1.0 / detail.scale == pytest.approx(longest)
    x, y = np.random.default_rng(4).uniform(0.0, 500.0, (2, 50_000))
    added = more.heights(x, y, 2.0) - source.heights(x, y, 2.0)
    assert detail.height * shading.NOISE_FAC_STD == pytest.approx(added.std(), rel=0.15)
    slopes = source.slopes
    drawn = drawn_slope(detail)
    assert drawn == pytest.approx(slopes.ripple, rel=1e-6)
    assert slopes.ripple == pytest.approx(
        slope_variance(more) - slope_variance(source), rel=0.10)
    assert slopes.shortest == pytest.approx(longest / 2**shading.RIPPLE_OCTAVES)
    # a steeper fractal's ripples halve from its last octave: no steeper than it
    for r in (0.8, 1.5):
        steep = HeightField(amplitude=0.8, wave_scale=30.0, octaves=6, roughness=r)
        last = steep.slopes.density * np.log(2.0)  # the last octave's slope variance
        assert steep.slopes.ripple == pytest.approx(shading.RIPPLE_OCTAVES * last)
    flat = HeightField(octaves=0)
    assert flat.ripple()[0].height == 0.0 and flat.slopes.ripple == 0.0
    assert shading.filtering(perspective(np.radians(40.0), 16 / 9, 0.1, 1e4), 960,
                             flat.slopes, 7.0).floor == pytest.approx(shading.cox_munk(7.0))


def test_a_pixel_s_footprint():
    """PIXELS (1) pixel's footprint: a pixel angle per metre of distance in perspective (twice
    the width, half the footprint), a pixel's size everywhere in an orthographic view; seen at
    cos to the sea plane, its major axis, 1 / cos times longer, at most GRAZING (9) times."""
    assert shading.PIXELS == 1.0 and shading.GRAZING == 9.0
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    pixel = 2.0 / (proj[0, 0] * 960)
    assert shading.pixel_footprint(proj, 960) == pytest.approx((np.log(pixel), 1.0))
    assert shading.pixel_footprint(proj, 1920)[0] == pytest.approx(
        shading.pixel_footprint(proj, 960)[0] - np.log(2.0))
    ortho = orthographic(50.0, 1.0, 0.1, 100.0)
    assert shading.pixel_footprint(ortho, 1000) == pytest.approx((np.log(50.0 / 1000), 0.0))
    f = shading.filtering(proj, 960, SpectralField(SeaState(wind_speed=7.0)).slopes, 7.0)
    at = [float(np.exp(footprint_log(f, 100.0, c))) for c in (1.0, 0.5, 0.2, 0.05)]
    assert at == pytest.approx([100.0 * pixel, 200.0 * pixel, 500.0 * pixel, 900.0 * pixel])


def roughness(f, distance, cos_view=1.0, lod=np.inf):
    """The roughness the water group draws (water_model.roughness), the gusts' factor 1."""
    i = group_inputs(f)
    lp = footprint_log(f, distance, cos_view)
    return water_model.roughness(NUMPY, i, lod, lp, water_model.ripples_undrawn(NUMPY, i, 1.0, lp))


def gust(fac, footprint, amplitude):
    """The gusts' factor (water_model.gust) at their noise's `fac`."""
    i = {"Gust Amplitude": amplitude, "Gust Norm": 1.0 / shading.gust_mean(amplitude)}
    return water_model.gust(NUMPY, i, np.asarray(fac, dtype=np.float64), footprint)


def facet_variance(f, distance, cos_view=1.0, sun_tan2=0.0):
    """The glint facets' slope variance (water_model.facet_variance) on a front face, the sun's
    half vector at tan^2 `sun_tan2` to the normal."""
    i = group_inputs(f)
    lp, log_cos = water_model.footprint(NUMPY, i, np.asarray(distance, float), cos_view)
    ripples = water_model.ripples_undrawn(NUMPY, i, 1.0, lp)
    return water_model.facet_variance(NUMPY, i, lp, log_cos, 1.0,
                                      1.0 / np.sqrt(1.0 + sun_tan2), 1.0, ripples)


def undrawn_ripples(f, distance, cos_view):
    return f.ripple * water_model.undrawn(NUMPY, f.ripple_top_log, f.shortest_log,
                                          footprint_log(f, distance, cos_view))


def slope_variance(source, t=2.0, n=100_000, e=0.005):
    """The mean square slope of a source's surface, by central differences at random points."""
    x, y = np.random.default_rng(6).uniform(0.0, 3000.0, (2, n))
    gx = (source.heights(x + e, y, t) - source.heights(x - e, y, t)) / (2 * e)
    gy = (source.heights(x, y + e, t) - source.heights(x, y - e, t)) / (2 * e)
    return float(np.mean(gx * gx + gy * gy))


@pytest.mark.parametrize("source", [
    SpectralField(SeaState(wind_speed=7.0), seed=2), SpectralField(SeaState(wind_speed=16.0)),
    HeightField(amplitude=0.8, wave_scale=30.0, octaves=6, method="exact")],
    ids=["spectrum 7 m/s", "spectrum 16 m/s", "noise"])
def test_the_slopes_drawn_are_the_surface_s(source):
    """The slope variance `slopes` reports for the geometry is the synthesised surface's (10 %):
    the filtering adds to it what the shader and the roughness carry."""
    slopes = source.slopes
    assert slope_variance(source) == pytest.approx(slopes.total - slopes.ripple, rel=0.10)


def spectrum_slopes(state, shortest, longest=2e4, samples=20_000):
    """The spectrum's slope variance from `shortest` to `longest` (m), integrated here anew."""
    k = np.geomspace(2 * np.pi / longest, 2 * np.pi / shortest, samples)
    w = np.sqrt(GRAVITY * k)
    s = spectrum.wind_spectrum(w, state) + spectrum.swell_spectrum(w, state)
    return float(integrate(k * k * s * np.gradient(w, k), k))


@pytest.mark.parametrize("u", [3.0, 6.0, 10.0, 15.0, 20.0])
def test_drawn_slopes_and_roughness_add_up_to_cox_munk(u):
    """At every distance the slope variance drawn (the geometry's bands, each by its band-limit
    weight squared, above the footprint, the slope layer's bands whole above it; the ripples'
    bump as drawn) plus the roughness of the
    rest is Cox and Munk's 0.003 + 5.12e-3 U(12.5 m) within 20 %, U(12.5 m) from U(10 m) by the
    log profile: on a grid one or four pixels a vertex, and with every band whole."""
    state = SeaState(wind_speed=u)
    source = SpectralField(state)
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    f = shading.filtering(proj, 1920, source.slopes, u)
    top = bands()[-1][0]
    ripple = source.slopes.ripple
    cox_munk = 0.003 + 5.12e-3 * u * np.log(12.5 / 2e-4) / np.log(10.0 / 2e-4)
    levels = [band_level(shortest) for shortest, _ in bands()]
    layer_top = bands()[LAYER_FIRST][1]
    for d in (1.0, 10.0, 100.0, 1e3, 1e4):
        for cos in (1.0, 0.05):
            lp = float(np.exp(footprint_log(f, d, cos)))
            spacing = lp / shading.PIXELS  # a vertex a pixel
            for lod in (np.inf, *band_limit.lod_for_spacing(1.0, [spacing, 4.0 * spacing])):
                drawn = 0.0
                for (shortest, longest), level in zip(bands(), levels,
                                                      strict=True):
                    if longest > lp:
                        weight = np.clip(lod - level, 0.0, 1.0)
                        if shortest < layer_top:  # the slope layer draws what they leave
                            weight = 1.0
                        drawn += weight**2 * spectrum_slopes(
                            state, max(shortest, lp),
                            longest if level > levels[0] else 2e4)
                # the shader keeps the ripple noise's octaves (each an octave band of equal
                # slopes, from 25 cm down) whose band lies above the footprint
                octaves = np.clip(np.log2(top / lp), 0.0, shading.RIPPLE_OCTAVES)
                drawn += f.ripple_gain**2 * ripple * octaves / shading.RIPPLE_OCTAVES
                rough = float(roughness(f, d, cos, lod))
                assert drawn + rough == pytest.approx(cox_munk, rel=0.20), (d, cos, lod, lp)
    assert float(roughness(f, 1.0)) < 0.1 * cox_munk  # near: drawn


@pytest.mark.parametrize("u", [2.0, 5.0, 8.0, 15.0])
def test_a_gust_roughens_the_ripples_as_cox_munk_says(u):
    """A gust one standard deviation strong (0.4 m/s up to a 5 m/s wind, 8 % of the wind
    above: J. Appl. Meteor. 27, 550, 1988) adds to the ripples' slope variance what Cox and
    Munk's 0.003 + 5.12e-3 U(12.5 m) grows by from the mean wind to the gust's (the longer
    waves unchanged), and a lull takes as much; the factor's mean is 1 over a symmetric noise."""
    spread = 0.4 if u <= 5.0 else 0.08 * u
    slopes = SpectralField(SeaState(wind_speed=u)).slopes

    def filtering(gusts=1.0):
        return shading.filtering(perspective(np.radians(40.0), 16 / 9, 0.1, 1e4), 1920, slopes,
                                 u, gusts)

    f = filtering()
    fac_std = GUST_FAC_STD
    assert GUST_SCALE == 1.0 / 30.0  # patches 30 m across
    for z in (1.0, -1.0):
        factor = float(gust(0.5 + z * fac_std, -10.0, f.gust))
        growth = 5.12e-3 * z * spread * np.log(12.5 / 2e-4) / np.log(10.0 / 2e-4)
        assert f.ripple * (factor - 1.0) == pytest.approx(growth, rel=1e-3), z  # gust_mean ~ 1
    # the factor's mean over a normal noise is 1, also where a lull's clip at flat water bites
    fac = 0.5 + fac_std * np.random.default_rng(5).standard_normal(400_000)
    for amplitude in (f.gust, 1.0, shading.GUST_CAP):
        factor = gust(fac, -10.0, amplitude)
        assert factor.min() >= 0.0 and factor.mean() == pytest.approx(1.0, abs=0.01), amplitude
    # a pixel as wide as a patch shows the ripples' mean
    assert float(gust(0.8, np.log(30.0), f.gust)) == 1.0
    # the Gusts setting scales the spread: 0 is a steady wind
    assert filtering(2.0).gust == pytest.approx(2.0 * f.gust) and filtering(0.0).gust == 0.0
    # a swing of its ripples many times over: capped
    assert filtering(100.0).gust == shading.GUST_CAP
    with pytest.raises(ValueError, match="gusts"):
        filtering(-1.0)


@pytest.mark.parametrize("u", [5.0, 12.0])
def test_the_slope_layer_holds_each_band_s_slopes(u):
    """Each band of the slope layer holds the spectrum's slope variance over the band (the
    integral of k^2 S) within 3 %, its tile as the spectrum says and as sampled, and its
    slopes are the gradient of its own height field."""
    state = SeaState(wind_speed=u)
    layer = SpectralField(state, seed=4).layer
    want = [spectrum_slopes(state, shortest, longest)
            for shortest, longest in bands()[slope_layer.LAYER_FIRST:]]
    assert layer.slope_variance() == pytest.approx(want, rel=0.03)
    drawn = [float(tile.var(axis=(1, 2)).sum()) for tile in layer.slopes(7.0)]
    assert drawn == pytest.approx(want, rel=0.1)
    for cascade in layer.cascades:
        h, sx, sy = cascade.samples(7.0, 0.0, (0, 3, 4))
        step = cascade.size / cascade.texels
        c, s = cascade.turn  # the tile's axes on the sea: x' = (c, s), y' = (-s, c)
        for axis, (ux, uy) in ((1, (c, s)), (0, (-s, c))):
            along = (np.roll(h, -1, axis=axis) - np.roll(h, 1, axis=axis)) / (2.0 * step)
            slope = ux * sx + uy * sy
            assert np.corrcoef(along.ravel(), slope.ravel())[0, 1] > 0.99


def test_the_slope_layer_s_lookups_find_its_texels():
    """A texel's point on the sea is at that texel's coordinates (the shader's lookup), from
    any origin."""
    layer = SpectralField(SeaState(wind_speed=9.0), seed=1).layer
    for cascade, (a, b, c) in zip(layer.cascades, layer.lookups((1234.0, -5678.0)),
                                  strict=True):
        i, j = 5, 17
        step = cascade.size / cascade.texels
        cos, sin = cascade.turn
        p = np.array([(i * cos - j * sin) * step, (i * sin + j * cos) * step, 0.0])
        p += cascade.size * np.array([cos * 3 - sin * 7, sin * 3 + cos * 7, 0.0])  # a repeat
        near = p - (1234.0, -5678.0, 0.0)
        s = (np.dot(a, near) + c[0]) % cascade.texels
        t = (np.dot(b, near) + c[1]) % cascade.texels
        assert (s, t) == pytest.approx((i, j), abs=1e-6)


def layer_gain(band, lod, footprint):
    return water_model.layer_gain(NUMPY, np.asarray(lod, dtype=np.float64), band.level,
                                  band.top_log, band.bottom_log, footprint)


def test_the_slope_layer_keeps_a_band_s_slopes_through_the_hand_over():
    """Where the vertices hold a band in part (weight g) and a pixel shows all of it, the
    geometry's g^2 and the layer's gain^2 add up to the whole band; past the footprint the
    layer keeps only the share of its waves still longer than it, and where the vertices hold
    the band whole it draws nothing."""
    band = SpectralField(SeaState(wind_speed=9.0)).layer.bands[0]
    lods = band.level + np.linspace(-1.0, 2.0, 31)
    g = np.clip(lods - band.level, 0.0, 1.0)
    gain = layer_gain(band, lods, band.bottom_log - 1.0)
    assert g**2 + gain**2 == pytest.approx(1.0)
    middle = 0.5 * (band.top_log + band.bottom_log)
    assert layer_gain(band, band.level - 1.0, middle) ** 2 == pytest.approx(0.5)
    assert layer_gain(band, band.level - 1.0, band.top_log + 0.1) == 0.0
    assert layer_gain(band, band.level + 1.0, band.bottom_log - 1.0) == 0.0


def test_the_detail_noise_draws_only_the_bands_above_the_layer():
    """The shader's noise detail stands for the left-out bands the slope layer does not draw,
    as high as their share of the sea, faded in from the band limit of its first band."""
    source = SpectralField(SeaState(wind_speed=15.0))
    first = 1
    detail = source.shader_detail(first, BANDS - first)
    bands_in = slope_layer.LAYER_FIRST - first
    assert detail.octaves == 2 * bands_in - 1
    assert detail.first == band_level(bands()[first][0])
    shares = band_shares(source.state)
    sigma = detail.height * shading.noise_fac_std(detail.octaves, detail.roughness)
    m0 = spectrum.moments(source.state)[0]
    assert sigma**2 == pytest.approx(m0 * sum(shares[first:slope_layer.LAYER_FIRST]), rel=1e-6)
    assert source.shader_detail(slope_layer.LAYER_FIRST, 3).height == 0.0


def test_the_glint_s_facets():
    """Half the ripples' shortest wave; a pixel whose footprint (a pixel's angle times the
    distance across, 1 / cos that along the view) holds at most FACETS_SHARP of them draws all
    the ripples' undrawn slopes as facets, one holding FACETS_MEAN or more none (the lobe
    then has them), fewer as the pixel holds more."""
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    source = SpectralField(SeaState(wind_speed=7.0))
    f = shading.filtering(proj, 960, source.slopes, 7.0)
    cell = source.slopes.shortest / 2.0
    assert np.exp(f.facet_log) == pytest.approx(cell)
    pixel = 2.0 / (proj[0, 0] * 960)
    d = np.geomspace(1.0, 3000.0, 400)
    for c in (1.0, 0.3, 0.05):
        facets = (pixel * d) ** 2 / max(c, 1.0 / shading.GRAZING) / cell**2
        undrawn = undrawn_ripples(f, d, c)
        drawn = facet_variance(f, d, c)
        sharp, mean = facets <= shading.FACETS_SHARP, facets >= shading.FACETS_MEAN
        assert drawn[sharp] == pytest.approx(undrawn[sharp])
        assert np.all(drawn[mean] == 0.0) and mean.any()
        between = ~sharp & ~mean & (undrawn > 0.0)
        assert between.any() and np.all(drawn[between] < undrawn[between])
        assert np.all(np.diff(drawn[between] / undrawn[between]) <= 1e-12)
    # only where a facet may show the sun: the half vector within SUN_REACH variances
    d, c = 20.0, 0.3
    full = facet_variance(f, d, c)
    undrawn = undrawn_ripples(f, d, c)
    assert full > 0.0
    assert facet_variance(f, d, c, 0.5 * shading.SUN_REACH * undrawn) == (
        pytest.approx(0.5 * full))
    assert facet_variance(f, d, c, shading.SUN_REACH * undrawn) == pytest.approx(
        0.0, abs=1e-9 * full)
