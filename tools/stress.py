"""The stability suite's checks on many fresh poses: `make stress` (100,000 poses, several minutes).

    python -m tools.stress [--poses N] [--seed S]   the worst error-to-tolerance ratio of each
                                                    check, the pose that gave it, and any failures
    python -m tools.stress --seed S --pose I        replay pose I of seed S alone: its ratios, and
                                                    the failing check's traceback if one fails

Poses come from tests/core/poses.py's decoder fed by a numpy stream (`fresh_poses`), so a seed and
an index name a pose exactly. A ratio above 1 fails its check; checks without a tolerance (finite
outputs, coverage, upward normals, ...) appear only among the failures. Exits 1 on any failure.
"""

import argparse
import os
import sys
import time
import traceback

from tests.core.grid_checks import RATIOS
from tests.core.poses import check_pose, fresh_poses

PROGRESS = 10_000


def run(pose):
    """Every check on one pose: its ratios, and the failing check's name (None if it passed)."""
    RATIOS.clear()
    try:
        check_pose(pose)
    except AssertionError as e:  # named by its message's head, or its line if it has none
        name = str(e).split(":")[0].split(" off by")[0]
        return dict(RATIOS), name or traceback.extract_tb(e.__traceback__)[-1].line or "assert"
    except Exception as e:  # a crash is a failure of the pose too: report it, keep going
        return dict(RATIOS), f"{type(e).__name__}: {e}"
    return dict(RATIOS), None


def replay(seed, index):
    _, _, pose = next(fresh_poses(seed, index + 1, first=index))
    print(f"pose {index} of seed {seed}: {pose}")
    ratios, failed = run(pose)
    for check, ratio in sorted(ratios.items()):
        print(f"  {check:<27} {ratio:.3g}")
    if failed is not None:
        check_pose(pose)  # again, for the traceback
    print("passed")
    return 0


def stress(seed, count):
    print(f"stress: {count:,} fresh poses, seed {seed}", flush=True)
    worst = {}  # check: (ratio, index, pose)
    failures = {}  # check: indices of the poses it failed
    start = time.perf_counter()
    for i, _, pose in fresh_poses(seed, count):
        ratios, failed = run(pose)
        for check, ratio in ratios.items():
            if check not in worst or ratio > worst[check][0]:
                worst[check] = (ratio, i, pose)
        if failed is not None:
            failures.setdefault(failed, []).append(i)
        if (i + 1) % PROGRESS == 0:
            print(f"  {i + 1:>9,} poses, {time.perf_counter() - start:6.0f} s, "
                  f"{sum(map(len, failures.values()))} failed", flush=True)
    seconds = time.perf_counter() - start
    print(f"\n{count:,} poses in {seconds:.0f} s ({1e3 * seconds / count:.1f} ms a pose), "
          f"seed {seed}\n\nworst error / tolerance (a check fails above 1):")
    for check, (ratio, i, _) in sorted(worst.items(), key=lambda kv: -kv[1][0]):
        print(f"  {check:<27} {ratio:10.3g}   pose {i}")
    print("\nthe poses that gave them (replay: python -m tools.stress "
          f"--seed {seed} --pose <index>):")
    for check, (_, i, pose) in sorted(worst.items(), key=lambda kv: -kv[1][0]):
        print(f"  {check} (pose {i}): {pose}")
    if not failures:
        print("\nno failures")
        return 0
    print("\nFAILURES:")
    for check, poses in sorted(failures.items(), key=lambda kv: -len(kv[1])):
        more = f" and {len(poses) - 20} more" if len(poses) > 20 else ""
        print(f"  {check}: {len(poses)} poses: {', '.join(map(str, poses[:20]))}{more}")
    return 1


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--poses", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=None, help="default: a fresh one")
    parser.add_argument("--pose", type=int, default=None, help="replay this pose of --seed alone")
    args = parser.parse_args(argv)
    if args.pose is not None:
        if args.seed is None:
            parser.error("--pose needs the --seed it came from")
        return replay(args.seed, args.pose)
    seed = int.from_bytes(os.urandom(8), "little") if args.seed is None else args.seed
    return stress(seed, args.poses)


if __name__ == "__main__":
    sys.exit(main())
