"""What a sweep (or a map) tells the user while it runs: a tqdm bar on a terminal, and the resume count.

The bar (count, rate and ETA, timed from the first design of this run) is drawn only when its
stream is a terminal and the user did not ask for quiet; the line saying how many designs an
earlier run had finished is written to the stream in every case, so a log shows what a resumed
run did.
"""

from __future__ import annotations

__all__ = ["Progress", "is_terminal"]


def is_terminal(stream) -> bool:
    """True when ``stream`` is an interactive terminal."""
    try:
        return bool(stream is not None and stream.isatty())
    except (AttributeError, ValueError, OSError):  # closed or file-less streams
        return False


class Progress:
    """Progress of one run of a sweep.

    Parameters
    ----------
    total : int
        Designs of the sweep.
    done_before : int
        Designs finished by earlier runs (counted, not timed).
    stream : text stream, optional
        Where to write (e.g. ``sys.stderr``); None writes nothing.
    bar : bool, optional
        Draw the tqdm bar; None (default): only when ``stream`` is a terminal.
    desc, unit : str
        The bar's label and what it counts.
    leave : bool
        Keep the bar on the terminal when it ends (else it is cleared).
    """

    def __init__(self, total: int, done_before: int = 0, stream=None, bar: bool | None = None, *,
                 desc: str = "sweep", unit: str = "design", leave: bool = True):
        self.total = int(total)
        self.done_before = int(done_before)
        self.count = 0
        self.stream = stream
        self.bar = is_terminal(stream) if bar is None else bool(bar and stream is not None)
        self._tqdm = None
        if self.bar:
            from tqdm import tqdm

            self._tqdm = tqdm(total=self.total, initial=self.done_before, file=stream, desc=desc,
                              unit=unit, mininterval=0.25, dynamic_ncols=True, leave=leave)

    def say(self, text: str) -> None:
        """Write one line (above the bar when it is drawn)."""
        if self.stream is None:
            return
        if self._tqdm is not None:
            self._tqdm.write(text, file=self.stream)
        else:
            self.stream.write(text + "\n")
            self.stream.flush()

    def update(self, n: int = 1) -> None:
        """Count ``n`` finished designs."""
        self.count += n
        if self._tqdm is not None:
            self._tqdm.update(n)

    def close(self) -> None:
        """End the bar (drawn in its final state)."""
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None
