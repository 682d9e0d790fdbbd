"""How a long in-process call shows its progress (a tqdm bar) and when Ctrl-C pauses it."""

import signal
import threading


def _sigint_pauses():
    """Whether SIGINT should pause an advance: only where Python itself would raise
    KeyboardInterrupt (the main thread, Python's default handler). An ignored SIGINT (a job
    started in the background or under nohup) stays ignored, and a handler of the user's own
    runs, as Python runs it, once advance returns."""
    return (threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler)


class _Bar:
    """A tqdm bar (tqdm.auto: the notebook widget or the terminal) over the run's fraction."""

    def __init__(self, label):
        from tqdm.auto import tqdm

        self._bar = tqdm(total=1000, desc=label, unit="‰", leave=True,
                         bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")
        self._n = 0

    def __call__(self, fraction):
        n = min(1000, max(self._n, int(round(1000 * fraction))))
        if n > self._n:
            self._bar.update(n - self._n)
            self._n = n

    def close(self):
        self._bar.close()
