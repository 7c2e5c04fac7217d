"""Make the repository root importable so `import projgrid_addon` works without Blender."""

import os
import sys

from hypothesis import settings

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

# CI replays the same examples every run (no flaky reds); developers get fresh ones each run.
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("dev", deadline=None, print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")


def pytest_terminal_summary(terminalreporter):
    """How often the stability suite's popping check compared a nudged grid."""
    suite = next((m for name, m in list(sys.modules.items())
                  if name.endswith("test_stability")), None)
    counts = getattr(suite, "POPPING", None)
    if counts and counts["poses"]:
        terminalreporter.write_line(
            f"popping check: compared {counts['compared']} of {counts['poses']} poses "
            f"({counts['compared'] / counts['poses']:.0%}; the rest not visible, at a heading "
            "singularity or seen edge-on)")
