"""Progress on a terminal for work that takes a while (animation frames, table rows): a tqdm bar
when tqdm (the ``progress`` extra) is installed, else a one-line counter; nothing when the stream
is not a terminal (a file, a pipe, CI), and nothing for work done within ``delay`` seconds.

>>> import io
>>> p = Progress("rows", io.StringIO())   # not a terminal: silent
>>> p(1, 2); p(2, 2)
"""

import sys
import time

DELAY = 2.0  # seconds of work before progress shows


class Progress:
    """Call as ``progress(done, total)`` after each piece of work."""

    def __init__(self, what, stream=None, delay=DELAY):
        self.what, self.stream, self.delay = what, stream or sys.stderr, delay
        self.on = bool(getattr(self.stream, "isatty", lambda: False)())
        self.start, self.shown, self.bar = time.monotonic(), False, None

    def __call__(self, done, total):
        if not self.on:
            return
        if self.bar is None:
            try:
                from tqdm import tqdm
            except ImportError:
                self.bar = False  # the counter below
            else:
                self.bar = tqdm(total=total, desc=self.what, file=self.stream, delay=self.delay, leave=False)
        if self.bar:
            self.bar.update(done - self.bar.n)
            if done >= total:
                self.bar.close()
        elif self.shown or time.monotonic() - self.start >= self.delay:
            self.shown = True
            self.stream.write(f"\r{self.what} {done}/{total}" + ("\n" if done >= total else ""))
            self.stream.flush()
