"""How a long in-process call shows its progress (a tqdm bar) and when Ctrl-C pauses it."""

import signal
import sys
import threading
import time


def sigint_pauses():
    """Whether SIGINT should pause an advance: only where Python itself would raise
    KeyboardInterrupt (the main thread, Python's default handler). An ignored SIGINT (a job
    started in the background or under nohup) stays ignored, and a handler of the user's own
    runs, as Python runs it, once advance returns."""
    return (threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler)


def _in_notebook():
    """Whether this runs in a Jupyter kernel, where tqdm.auto draws its widget (or its text)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})


class ProgressBar:
    """The run's fraction as a tqdm bar where someone watches it (a terminal: tqdm's text bar; a
    notebook: tqdm's widget, or its text bar where the widget cannot be drawn), else as one line
    when it ends: a bar redrawn into a log or a pipe leaves its partial states behind
    (`0%|...100%|`)."""

    def __init__(self, label, stream=None):
        self._stream = sys.stderr if stream is None else stream
        self._label, self._n, self._start = label, 0, time.monotonic()
        self._bar = None
        notebook = _in_notebook()
        if notebook or _isatty(self._stream):
            if notebook and _widgets_usable():
                from tqdm.notebook import tqdm
            else:  # a terminal, or a notebook's text output, which redraws at a carriage return
                from tqdm.std import tqdm

            self._bar = tqdm(total=1000, desc=label, unit="‰", leave=True, file=self._stream,
                             bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")

    def __call__(self, fraction):
        n = min(1000, max(self._n, int(round(1000 * fraction))))
        if n > self._n:
            if self._bar is not None:
                self._bar.update(n - self._n)
            self._n = n

    def close(self):
        if self._bar is not None:
            self._bar.close()
        else:
            elapsed = time.monotonic() - self._start
            print(f"{self._label}: {self._n // 10}% in {elapsed:.3g} s", file=self._stream, flush=True)


def _widgets_usable():
    """Whether tqdm's notebook widget can be drawn: ipywidgets 7 or later. Debian 12's
    ipywidgets 6 speaks an older widget protocol, which nbclient (jupyter nbconvert --execute)
    cannot take: the execution stops with KeyError 'state'."""
    try:
        import ipywidgets
    except ImportError:
        return False
    try:
        return int(str(ipywidgets.__version__).split(".")[0]) >= 7
    except ValueError:
        return False


def _isatty(stream):
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False
