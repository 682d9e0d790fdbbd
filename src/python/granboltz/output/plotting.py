"""Plotting helpers with the house style (a printed paper's look): pyplot on the Agg backend,
reproducible figure files, and the JSON summary each figure rule writes beside its figure.

matplotlib is imported only when pyplot() is called.
"""

import os

from .files import atomic_path


def house_style():
    """The house style (a printed paper's look) as matplotlib rcParams, for plt.rc_context."""
    return {
        "font.family": "serif",
        "font.serif": ["DejaVu Serif"],
        "mathtext.fontset": "dejavuserif",
        "font.size": 9,
        "axes.labelsize": 9,
        "axes.titlesize": 9,
        "axes.linewidth": 0.6,
        "legend.fontsize": 8,
        "legend.frameon": False,
        "lines.linewidth": 0.8,
        "xtick.direction": "in",
        "ytick.direction": "in",
        "xtick.top": True,
        "ytick.right": True,
        "xtick.major.width": 0.6,
        "ytick.major.width": 0.6,
        "savefig.dpi": 200,
        "savefig.bbox": "tight",
        "savefig.pad_inches": 0.02,
    }


def pyplot():
    """matplotlib.pyplot on the Agg backend with the house style (a printed paper's look)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(house_style())
    return plt


SONINE_TITLES = {"gaussian": "Gaussian thermostat (HCS)", "white_noise": "white noise (steady)"}


def label_sonine_panels(axes, thermostats=("gaussian", "white_noise")):
    """Titles, zero lines and axis labels of a 2 x 2 grid of Sonine coefficients: a2 on the top row,
    a3 below, one column per thermostat."""
    for column, thermostat in enumerate(thermostats):
        top, bottom = axes[:, column]
        for ax in (top, bottom):
            ax.axhline(0.0, color="grey", lw=0.4)
        top.set_title(SONINE_TITLES[thermostat])
        bottom.set_xlabel("$\\alpha$")
    axes[0, 0].set_ylabel("$a_2$")
    axes[1, 0].set_ylabel("$a_3$")


def save_figure(fig, paths):
    """Save `fig` to each path (format from the extension), each atomically, then close it (pyplot
    keeps every open figure, and the tests run many scripts in one process); PDFs carry no
    creation date, so a rerun gives the same bytes."""
    for path in paths:
        fmt = os.path.splitext(path)[1][1:]
        metadata = {"CreationDate": None} if fmt == "pdf" else None
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, metadata=metadata)
    import matplotlib.pyplot as plt

    plt.close(fig)


def figure_summary(ours, short, kind=None, **numbers):
    """The JSON summary a figure rule writes next to its figure: the one-line description of
    what our figure shows (`ours`, computed from the numbers), a shorter one for the report's
    summary table (`short`), the outcome the script computed (`kind`: agrees, questioned,
    approximation or differs; without it the report reads it from the words of `short`) and the
    numbers themselves."""
    out = {"ours": ours, "short": short, "numbers": numbers}
    if kind is not None:
        out["kind"] = kind
    return out
