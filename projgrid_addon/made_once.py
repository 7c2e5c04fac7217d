"""Values made once across threads: kept per source (weakly) and key, the newest KEPT a
source. A value `reserve`d by a worker and then `start`ed is waited for, not made twice; one
reserved but not started is made by whoever needs it first, so a caller never waits for a
worker's queue, only for a value being made (foam.Calibrations: the whitecap calibrations the
Blender layer's worker makes ahead). A cache of pure functions: never changes a value."""

import contextlib
import threading
import weakref


class MadeOnce:
    """Values kept per source and key (a subclass sets KEPT, how many a source keeps)."""

    def __init__(self):
        self._made = weakref.WeakKeyDictionary()  # source -> {key: value}
        self._making = {}  # (id(source), key) -> threading.Event
        self._started = set()  # of those, the (id(source), key) someone is making now
        self._lock = threading.Lock()
        # entered while a caller stalls on a value, waiting for it or making it (the Blender
        # layer's: its worker, which waits while a frame is built, goes on meanwhile)
        self.stalled = contextlib.nullcontext

    def made(self, source, key, make):
        """The value of `source` at `key`: kept, waited for while another makes it, or made
        here by `make()` (taking over a reserved one not started)."""
        with self._lock:
            made = self._made.get(source, {}).get(key)
            making = self._making.get((id(source), key))
            mine = made is None and making is not None and (id(source), key) not in self._started
            if mine:  # reserved, not started: made here, the worker skips it
                self._started.add((id(source), key))
        if made is None and making is not None and not mine:
            with self.stalled():
                making.wait()
            with self._lock:
                made = self._made.get(source, {}).get(key)
        if made is None:
            try:
                with self.stalled():
                    made = make()
                self.put(source, key, made)
            finally:
                if mine:
                    self.release(source, key)
        return made

    def start(self, source, key):
        """Whether the caller is to make the reserved `key` now (False: another took it over,
        and releases it)."""
        with self._lock:
            if (id(source), key) not in self._making or (id(source), key) in self._started:
                return False
            self._started.add((id(source), key))
            return True

    def has(self, source, key):
        """Whether `key` is made or being made."""
        with self._lock:
            return key in self._made.get(source, {}) or (id(source), key) in self._making

    def reserve(self, source, keys):
        """Of `keys`, those neither made nor being made, now marked as being made (by the
        caller, who then `start`s, `put`s and `release`s each, or `release`s it)."""
        with self._lock:
            free = [k for k in keys if k not in self._made.get(source, {})
                    and (id(source), k) not in self._making]
            for key in free:
                self._making[id(source), key] = threading.Event()
        return free

    def put(self, source, key, made):
        """Keep `made` as `key`'s, the source's oldest dropped past KEPT."""
        with self._lock:
            made_here = self._made.setdefault(source, {})
            made_here[key] = made
            for old in list(made_here)[:-self.KEPT]:
                del made_here[old]

    def release(self, source, key):
        """No longer being made (made, or failed): whoever waits for it goes on."""
        with self._lock:
            making = self._making.pop((id(source), key), None)
            self._started.discard((id(source), key))
        if making is not None:
            making.set()

    def making(self):
        """How many values are being made."""
        with self._lock:
            return len(self._making)
