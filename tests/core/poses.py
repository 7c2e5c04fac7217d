"""The stability suite's poses: a byte-string decoder shared by hypothesis (tests), the fresh-seed
batch and tools/stress.py, and `check_pose`, which runs every property on one pose.

Each property records its worst error-to-tolerance ratio in `grid_checks.RATIOS` before it asserts,
so the stress run can report how close to its tolerance each came.
"""

import dataclasses

import numpy as np
from hypothesis import strategies as st

from .grid_checks import (
    Pose,
    check_coverage,
    check_result,
    heading_margin,
    record,
    relative_moves,
    seen_edge_on,
)


class Draw:
    """Decodes one hypothesis byte string into pose parameters.

    Drawing each of ~20 parameters separately costs hypothesis ~6 ms per pose, more than the checks;
    one `st.binary` draw costs ~0.1 ms. Every parameter reads a fixed slot of 4 bytes, so the layout
    is stable, and bytes shrink toward zero, which decodes to the first branch and the low end of
    each range: shrunk failures stay readable.
    """

    def __init__(self, data):
        self.u = np.frombuffer(data, dtype="<u4") / 2.0**32  # uniform in [0, 1)
        self.i = 0

    def unit(self):
        self.i += 1
        return float(self.u[self.i - 1])

    def pick(self, *options):
        return options[int(self.unit() * len(options))]

    def uniform(self, lo, hi):
        return lo + self.unit() * (hi - lo)

    def log_uniform(self, lo, hi):
        """For scales spanning decades (clip range, distance, time): every decade equally often."""
        return float(lo * (hi / lo) ** self.unit())

    def integer(self, lo, hi):
        return lo + int(self.unit() * (hi - lo + 1))


SLOTS = 48


def pose_from_bytes(data):
    d = Draw(data)
    amplitude = d.pick(0.0, d.uniform(0.0, 3.0), d.log_uniform(1e-3, 200.0))
    octaves = d.integer(0, 10)
    roughness = d.uniform(0.0, 1.0)
    bound = amplitude * sum(roughness**i for i in range(octaves))
    height = d.pick(
        d.uniform(-50.0, 10_000.0),
        d.log_uniform(1e-3, 10_000.0),
        d.uniform(-bound - 1.0, bound + 1.0),  # inside or next to the displaceable volume
        d.pick(0.0, bound, -bound),
    )
    # Clip start and end drawn independently over all a Blender camera allows in practice; a far
    # clip not beyond the near one (which Blender refuses) is redrawn above it.
    near = d.log_uniform(1e-6, 10.0)
    far = d.log_uniform(1e-2, 1e9)
    if far <= 1.01 * near:
        far = d.log_uniform(1.01 * near, 1e9)
    ortho_scale = d.log_uniform(0.1, 1e4) if d.unit() < 0.25 else 0.0  # one pose in four
    pose = Pose(
        height=height,
        pitch=d.pick(d.uniform(-90.0, 90.0), d.uniform(-15.0, 15.0), d.pick(-90.0, 0.0, 90.0)),
        yaw=d.uniform(-180.0, 180.0),
        roll=d.pick(d.uniform(-180.0, 180.0), d.pick(0.0, 90.0, 180.0)),
        fov=d.pick(d.uniform(1.0, 170.0), d.log_uniform(1.0, 170.0)),
        ortho_scale=ortho_scale,
        near=near,
        far=far,
        distance=d.pick(0.0, d.log_uniform(1e-3, 1e6)),
        bearing=d.uniform(0.0, 360.0),
        aspect=d.log_uniform(0.25, 4.0),
        shift_x=d.uniform(-0.5, 0.5),
        shift_y=d.uniform(-0.5, 0.5),
        level=d.uniform(-100.0, 100.0),
        amplitude=amplitude,
        octaves=octaves,
        roughness=roughness,
        time=d.pick(0.0, d.log_uniform(1e-3, 1e7)),
        elevation=d.pick(0.0, d.uniform(0.0, 50.0)),
        resolution=(d.integer(2, 12), d.integer(2, 12)),
        # The fast path renders its textures per time slice (~3 ms a pose); the grid's geometry
        # is the same for either path, so most random poses take the exact one.
        method=d.pick("exact", "exact", "exact", "fast"),
        # Choppy in one pose of two, up to past folding (lambda a k > 1 on the steep octaves).
        choppiness=d.pick(0.0, d.uniform(0.0, 2.0)),
        wind_direction=d.uniform(-np.pi, np.pi),
    )
    # One pose in ten is the spectral sea (Add Ocean's), from a few seas so that each is made
    # once (grid_checks._spectral keeps them): its thin fitted volume and choppy bound.
    if d.unit() < 0.1:
        pose = dataclasses.replace(pose, wind_speed=d.pick(4.0, 10.0, 20.0),
                                   choppiness=d.pick(0.0, 1.5), wind_direction=d.pick(0.0, 2.0))
    assert d.i <= SLOTS
    return pose


poses = st.binary(min_size=4 * SLOTS, max_size=4 * SLOTS).map(pose_from_bytes)


def nudged(pose, eps):
    """The same pose moved by a relative `eps`: position by eps times the distance to the volume's
    far side (the scale the projector sees), angles by eps."""
    bound = pose.height_field().bounds(pose.time)[0]
    step = eps * max(abs(pose.height), bound + pose.elevation)
    deg = np.degrees(eps)
    return Pose(**{**pose.__dict__, "height": pose.height + step, "pitch": pose.pitch + deg,
                   "yaw": pose.yaw + deg, "roll": pose.roll + deg,
                   "distance": pose.distance + step})


# Popping is a discontinuity: a vertex that jumps however small the camera move. So the camera is
# moved by a relative EPS (far above float64 rounding) and no vertex may move more than POP of its
# distance from the projector (which stays above the volume, so the ratio never degenerates).
# A continuous grid moves by about EPS times its conditioning; a jump does not shrink with EPS.
# The nudged grid keeps the first one's displaceable volume: which fitted volume the border check
# keeps changes in steps by design (the benchmark counts how often), the projector's maths must not.
EPS = 1e-9
POP = 1e-2


# How often the popping check compared a nudged grid, of the poses it was given (printed at the
# end of the run: its exclusions must not quietly swallow the suite).
POPPING = {"poses": 0, "compared": 0}


def check_no_popping(pose, result):
    POPPING["poses"] += 1
    if not result.visible or pose.pitch + np.degrees(EPS) > 90.0:
        return
    camera = pose.camera()
    # No continuous projector heading exists for every orientation (projector.heading); its
    # singular poses are left out of this one property, as are views that see the surface edge-on.
    bound = pose.height_field().bounds(pose.time)[0]
    if heading_margin(camera) < 0.05 or seen_edge_on(camera, pose.level, bound):
        return
    _, moved = nudged(pose, EPS).build(extent=result.extent)
    if not moved.visible:
        return
    POPPING["compared"] += 1
    move, rounding = relative_moves(result, moved)
    jump = float(np.max(move - rounding))
    record("popping", jump / POP)
    assert jump <= POP, f"popping: a vertex jumped {jump:.3g} of its reach"


def check_pose(pose, popping=True, **build):
    camera, result = pose.build(**build)
    bound = pose.height_field().bounds(pose.time)[0]
    check_result(camera, result, pose.level, bound)
    check_coverage(camera, result, pose.level, bound)
    if popping:
        check_no_popping(pose, result)
    return camera, result


def fresh_bytes(rng):
    """One pose's bytes from a numpy Generator: each slot uniform, or with probability 1/8 either
    end of its range (hypothesis favours the ends too: straight down, clip extremes, full shift)."""
    u = rng.integers(0, 2**32, SLOTS, dtype=np.uint64)
    end = rng.random(SLOTS) < 0.125
    u[end] = np.where(rng.random(int(end.sum())) < 0.5, 0, 2**32 - 1)
    return u.astype("<u4").tobytes()


def fresh_poses(seed, count, first=0):
    """(index, bytes, pose) for poses first .. count - 1 of the stream `seed` names: a pose is
    replayed from its seed and index alone."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        data = fresh_bytes(rng)
        if i >= first:
            yield i, data, pose_from_bytes(data)
