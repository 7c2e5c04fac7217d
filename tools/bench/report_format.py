"""What every section of the benchmark report builds with: its shared page state (`Report`,
`Target`), tables, spreads and plots."""

import os
from dataclasses import dataclass, field

import numpy as np


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _spread(prefix="", unit="ms", fmt=".2f", label="ms"):
    """Table columns for the 10th percentile and CPU time beside a median (nan in a row that
    lacks them)."""
    def column(kind):
        key = f"{prefix}{kind}_{unit}"
        return lambda r: r.get(key, float("nan"))

    return [(f"p10 {label}", column("p10"), fmt), (f"CPU {label}", column("cpu"), fmt)]


def _table(rows, columns):
    """Markdown table; columns = [(header, key or function, format)]."""
    out = ["| " + " | ".join(h for h, _, _ in columns) + " |",
           "|" + "|".join(" --- " for _ in columns) + "|"]
    for r in rows:
        cells = []
        for _, key, fmt in columns:
            v = key(r) if callable(key) else r[key]
            cells.append(format(v, fmt) if fmt else str(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def _maybe(key, fmt):
    """A _table column of `key` formatted by `fmt`, a dash where a row has none."""
    return lambda r: format(r[key], fmt) if key in r else "—"


def _finish(ax, xlabel, ylabel, legend_size=None):
    """Labels, grid (minor lines too on log axes) and legend of one plot."""
    ax.set_xlabel(xlabel)
    if ylabel:
        ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    if legend_size is not None:
        ax.legend(fontsize=legend_size)


def _save(fig, docs, name):
    """Lay out and write docs/<name>.png, free the figure; returns its Markdown image line."""
    fig.tight_layout()
    fig.savefig(os.path.join(docs, f"{name}.png"), dpi=110)
    _plt().close(fig)
    return f"![{name.removeprefix('bench_')}]({name}.png)"


def _loglog_slope(x, y):
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


@dataclass
class Target:
    """A goal the benchmark checks, what was measured, and what is missing and why when the
    measurement falls short (shown under the targets table)."""

    name: str
    measured: str
    met: bool
    why: str = ""


@dataclass
class Report:
    """What the sections share: the results, where the plots go, and the page being written."""

    results: dict
    docs: str
    plt: object
    md: list = field(default_factory=list)
    targets: list = field(default_factory=list)
