"""A thread-safe LRU cache bounded by bytes and by entries, with single-flight filling.

Used for what is read or derived from the immutable result files of finished jobs (channel
arrays, file descriptions, rendered API answers): the API answers reads from several threads
at once, so every operation takes a lock, and concurrent misses of one key compute the value
once (the others wait for it) instead of all reading the same file at the same time.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from typing import Any

_MISSING = object()


@dataclass(frozen=True)
class CacheStats:
    """Counters of a :class:`ByteLRU`.

    Attributes
    ----------
    entries : int
        Entries held.
    bytes : int
        Their accounted size in bytes.
    max_bytes, max_entries : int
        The bounds.
    hits, misses, evictions : int
        Lookups answered, lookups not answered, entries evicted by the bounds since creation.
    """

    entries: int
    bytes: int
    max_bytes: int
    max_entries: int
    hits: int
    misses: int
    evictions: int


class ByteLRU:
    """Least-recently-used cache of values with a size in bytes.

    Parameters
    ----------
    max_bytes : int
        Most bytes held (sum of the sizes given to :meth:`put`); 0 disables the cache.
    max_entries : int
        Most entries held.
    max_entry_fraction : float
        A value larger than this fraction of ``max_bytes`` is not kept (one huge answer must
        not flush everything else).
    """

    def __init__(self, max_bytes: int, max_entries: int = 4096,
                 max_entry_fraction: float = 0.25):
        self.max_bytes = max(0, int(max_bytes))
        self.max_entries = max(0, int(max_entries))
        self.max_entry_bytes = int(self.max_bytes * max_entry_fraction)
        self._data: OrderedDict[Hashable, tuple[Any, int]] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()
        self._flights: dict[Hashable, threading.Lock] = {}
        self._hits = self._misses = self._evictions = 0

    def get(self, key: Hashable, default: Any = None) -> Any:
        """The value of ``key`` (now the most recently used) or ``default``."""
        with self._lock:
            item = self._data.get(key)
            if item is None:
                self._misses += 1
                return default
            self._data.move_to_end(key)
            self._hits += 1
            return item[0]

    def put(self, key: Hashable, value: Any, nbytes: int) -> bool:
        """Keep ``value`` (``nbytes`` bytes) under ``key``, evicting the least recently used
        entries beyond the bounds; False (nothing kept) if it is too large to keep.
        """
        nbytes = max(1, int(nbytes))
        if nbytes > self.max_entry_bytes or self.max_entries == 0:
            return False
        with self._lock:
            old = self._data.pop(key, None)
            if old is not None:
                self._bytes -= old[1]
            self._data[key] = (value, nbytes)
            self._bytes += nbytes
            while self._bytes > self.max_bytes or len(self._data) > self.max_entries:
                _, (_, size) = self._data.popitem(last=False)
                self._bytes -= size
                self._evictions += 1
        return True

    def get_or_make(self, key: Hashable, make: Callable[[], tuple[Any, int]]) -> Any:
        """The value of ``key``, made by ``make() -> (value, nbytes)`` and kept on a miss.

        Concurrent misses of the same key call ``make`` once: the other callers wait and take
        its value. Exceptions of ``make`` propagate and nothing is kept.
        """
        value = self.get(key, _MISSING)
        if value is not _MISSING:
            return value
        with self._lock:
            flight = self._flights.setdefault(key, threading.Lock())
        try:
            with flight:
                value = self.get(key, _MISSING)
                if value is _MISSING:
                    value, nbytes = make()
                    self.put(key, value, nbytes)
                return value
        finally:
            with self._lock:
                if self._flights.get(key) is flight:
                    del self._flights[key]

    def discard(self, match: Callable[[Any], bool]) -> int:
        """Remove the entries whose key satisfies ``match``; return how many."""
        with self._lock:
            gone = [k for k in self._data if match(k)]
            for k in gone:
                self._bytes -= self._data.pop(k)[1]
        return len(gone)

    def keys(self) -> list[Any]:
        """The keys held, least recently used first."""
        with self._lock:
            return list(self._data)

    def clear(self) -> None:
        """Remove every entry."""
        with self._lock:
            self._data.clear()
            self._bytes = 0

    def stats(self) -> CacheStats:
        """Current size, bounds and counters."""
        with self._lock:
            return CacheStats(entries=len(self._data), bytes=self._bytes,
                              max_bytes=self.max_bytes, max_entries=self.max_entries,
                              hits=self._hits, misses=self._misses,
                              evictions=self._evictions)
