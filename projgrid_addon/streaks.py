"""Foam the wind blows into streaks (NumPy-free): how drawn out along the wind the whitecaps'
aged foam is, how much of their residual foam it gathers, and the streaks the wind blows off
the crests besides (WMO's Beaufort descriptions; Holthuijsen, Powell and Pietrzak 2012)."""

from . import residual_foam

# m/s: the winds over which the aged foam's streaks draw out along the wind, from round
# patches (Beaufort 6's 10.8-13.8 m/s: "white foam crests everywhere") to STREAK_MOST times
# longer than wide (Beaufort 8, from 17.2 m/s: "foam blown in well-marked streaks"; WMO), and
# gather more of the residual foam (`streak_share`).
STREAK_WINDS = (12.0, 17.5)
STREAK_MOST = 10.0
STREAK_SHARE_MOST = 0.6
# m/s: the winds over which the blown streaks grow from none to covering the sea: from
# Beaufort 7's lower limit (13.9 m/s, WMO: "white foam from breaking waves begins to be blown
# in streaks along the direction of the wind") to the white-out Holthuijsen et al. (2012)
# observed in hurricanes ("at surface wind speeds of about 40 m/s the streaks merge into a
# white out"); between, as the square of the way there (`blown_coverage`).
BLOWN_WINDS = (13.9, 40.0)


def _ramp(wind_speed, winds):
    """0 to 1 over `winds`."""
    return min(max((float(wind_speed) - winds[0]) / (winds[1] - winds[0]), 0.0), 1.0)


def foam_streak(wind_speed):
    """How many times longer along the wind than across it the aged foam's streaks are."""
    return 1.0 + (STREAK_MOST - 1.0) * _ramp(wind_speed, STREAK_WINDS)


def streak_share(wind_speed):
    """The share of the residual foam drawn as streaks, not where it fell: the aged foam
    (residual_foam.aged_share), and from STREAK_WINDS[0] up, as the streaks draw out, up to
    STREAK_SHARE_MOST of the young foam's too, within Monahan's whitecap coverage."""
    aged = residual_foam.aged_share()
    return aged + (1.0 - aged) * STREAK_SHARE_MOST * _ramp(wind_speed, STREAK_WINDS)


def blown_coverage(wind_speed):
    """The share of the sea the streaks the wind blows off the crests cover, besides the
    whitecaps and their foam (Monahan's share): Holthuijsen et al. found the whitecaps' share
    level off at high winds and the streaks join them, increasingly dominating. Over
    BLOWN_WINDS, as the square of the way: at 19-23 m/s (Beaufort 8-9, "well-marked" to "dense
    streaks") as much as the whitecaps' share to 2.5 times it, as Ross and Cardone (1974) found
    the thin streaks add at 10-25 m/s (whitecap photographs agree with Monahan-like shares
    only with the streaks left out); Beaufort 10 (26.5 m/s) a quarter of the sea ("a white
    appearance"), 11 (30.5 m/s) two fifths ("completely covered with long white patches").
    The share is the mean cover: drawn as a film of look.AGED_FILM, over a third more of the
    sea."""
    return _ramp(wind_speed, BLOWN_WINDS) ** 2
