"""A recording's writer thread: drains the queue of ticks into the episode's rosbag2 file.

Each tick's samples are serialised and written through
:class:`episodes.streams.bagwrite.BagWriter` (MCAP with chunk, data and summary CRCs), then its
``/engram/ticks`` record; a provider's record goes in before its first sample. Every
``flush_interval_s`` the current chunk is closed and the file flushed (and each full chunk is
passed to the operating system as soon as it is written), so a crash loses at most that much.
A write error stops the writing: the file is aborted and every sample after it is counted as
dropped (``write_error``) in the :class:`~episodes.streams.ledger.Ledger`, never lost silently.
"""

import json
import logging
import queue
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from episodes.streams import messages
from episodes.streams.bagwrite import BagWriter
from episodes.streams.ledger import Ledger, Tick
from episodes.streams.messages import PROVIDER_TYPE, TICK_TYPE

__all__ = ["FORMAT_VERSION", "PROVIDERS_TOPIC", "RECORDING_TOPIC", "TICKS_TOPIC", "TickWriter"]

log = logging.getLogger(__name__)

TICKS_TOPIC = "/engram/ticks"
PROVIDERS_TOPIC = "/engram/providers"
RECORDING_TOPIC = "/engram/recording"
FORMAT_VERSION = 1


class TickWriter:
    """The writer thread of one recording into the new bag directory ``path``, started at once.

    ``clock`` gives the time of provider records written before any tick (ns since the epoch);
    the other settings are :class:`episodes.streams.recorder.Recorder`'s. Raises
    :class:`~episodes.streams.errors.RecordingStateError` if the file cannot be created.
    """

    def __init__(
        self,
        path: Path,
        *,
        episode_id: str,
        ledger: Ledger,
        compression: str | None,
        flush_interval_s: float,
        fsync: bool,
        clock: Callable[[], int],
    ) -> None:
        self.episode_id = episode_id
        self.cpu_s = 0.0
        """CPU time the thread spent, once it has finished."""
        self._ledger = ledger
        self._flush_interval_s = flush_interval_s
        self._fsync = fsync
        self._clock = clock
        self._queue: queue.SimpleQueue[Tick | threading.Event | None] = queue.SimpleQueue()
        self._ts = messages.typestore()
        self.bag = BagWriter(
            path,
            typestore=self._ts,
            compression=compression,
            custom_data={"engram.episode": episode_id, "engram.format": str(FORMAT_VERSION)},
        )
        self._connections: dict[str, int] = {}
        for topic, msgtype in (
            (RECORDING_TOPIC, "std_msgs/msg/String"),
            (PROVIDERS_TOPIC, PROVIDER_TYPE),
            (TICKS_TOPIC, TICK_TYPE),
        ):
            self._connections[topic] = self.bag.add_connection(topic, msgtype)
        self._started = False
        self._thread = threading.Thread(
            target=self._run, name=f"engram-recorder-{episode_id}", daemon=True
        )
        self._thread.start()

    def put(self, tick: Tick) -> None:
        """Queue a tick to be written (its bytes already reserved in the ledger)."""
        self._queue.put(tick)

    def request_flush(self) -> threading.Event:
        """Ask for everything queued so far to be written and flushed; the event is set once
        it is (or once the writer has failed)."""
        done = threading.Event()
        self._queue.put(done)
        return done

    def finish(self, timeout_s: float) -> None:
        """Write what is queued, complete the file and end the thread; raises
        :class:`TimeoutError` if that takes longer than ``timeout_s``. Call it once, with
        nothing queued after it."""
        self._queue.put(None)
        self._thread.join(timeout_s)
        if self._thread.is_alive():
            raise TimeoutError(f"the writer did not finish within {timeout_s} s")

    def _run(self) -> None:
        ledger = self._ledger
        cpu0 = time.thread_time()
        last_flush = time.monotonic()
        try:
            while True:
                item = self._queue.get()
                if item is None:
                    break
                if isinstance(item, threading.Event):
                    if ledger.failure is None:
                        self._write_pending_providers(self._record_time())
                        self.bag.flush(fsync=self._fsync)
                    item.set()
                    continue
                if ledger.failure is not None:
                    ledger.count_write_errors(item, release=True)
                    continue
                try:
                    self._write_tick(item)
                    now = time.monotonic()
                    if now - last_flush >= self._flush_interval_s:
                        self.bag.flush(fsync=self._fsync)
                        last_flush = now
                    else:
                        self.bag.pass_on()  # a chunk the library completed
                except Exception as exc:  # disk full, I/O error: count, never lose silently
                    log.exception("episode %s: writing failed", self.episode_id)
                    ledger.failure = exc
                    ledger.count_write_errors(item, release=False)
            if ledger.failure is None:
                self._write_pending_providers(self._record_time())
                self.bag.close()
            else:
                self.bag.abort()
        except Exception as exc:
            log.exception("episode %s: closing the bag failed", self.episode_id)
            ledger.failure = exc
        finally:
            self.cpu_s = time.thread_time() - cpu0

    def _record_time(self) -> int:
        # provider records written outside a tick: at the last tick, or now if none yet
        last = self._ledger.last_tick_ns
        return last if last > 0 else max(self._clock(), 1)

    def _write_pending_providers(self, time_ns: int) -> None:
        with self._ledger.lock:
            pending = [p for p in self._ledger.providers.values() if not p.written]
        if not pending:
            return
        types = self._ts.types
        if not self._started:
            self._started = True
            record = json.dumps({"episode": self.episode_id, "format": FORMAT_VERSION})
            data = self._ts.serialize_cdr(
                types["std_msgs/msg/String"](data=record), "std_msgs/msg/String"
            )
            self.bag.write(self._connections[RECORDING_TOPIC], time_ns, data)
        for provider in pending:
            spec = provider.spec
            baseline = spec.baseline
            msg = types[PROVIDER_TYPE](
                name=spec.name,
                kind=spec.kind.value,
                topic=spec.topic,
                config_json=messages.config_json(spec),
                baseline=(
                    np.frombuffer(baseline.tobytes(), dtype=np.uint8)
                    if baseline is not None
                    else np.zeros(0, dtype=np.uint8)
                ),
            )
            self._connections[spec.topic] = self.bag.add_connection(spec.topic, spec.msgtype)
            self.bag.write(
                self._connections[PROVIDERS_TOPIC],
                time_ns,
                self._ts.serialize_cdr(msg, PROVIDER_TYPE),
            )
            provider.written = True

    def _write_tick(self, tick: Tick) -> None:
        self._write_pending_providers(tick.time_ns)
        names: list[str] = []
        stamps: list[int] = []
        stored: list[int] = []
        sizes: list[int] = []
        spent: list[float] = []
        try:
            for provider, stamp, value, _size in tick.samples:
                began = time.perf_counter()
                spec = provider.spec
                names.append(spec.name)
                stamps.append(stamp)
                sparse = None
                if spec.baseline is not None:
                    sparse = messages.sparse_of(spec, value)
                    if sparse is None:
                        stored.append(0)
                        sizes.append(0)
                        spent.append(time.perf_counter() - began)
                        continue
                msg = messages.encode(spec, stamp, value, sparse)
                data = self._ts.serialize_cdr(msg, spec.msgtype)
                self.bag.write(self._connections[spec.topic], tick.time_ns, data)
                stored.append(1)
                sizes.append(len(data))
                spent.append(time.perf_counter() - began)
            record = self._ts.types[TICK_TYPE](
                frame=tick.frame,
                tick_time_ns=tick.time_ns,
                providers=names,
                stamps_ns=np.asarray(stamps, dtype=np.int64),
                stored=np.asarray(stored, dtype=np.uint8),
            )
            self.bag.write(
                self._connections[TICKS_TOPIC],
                tick.time_ns,
                self._ts.serialize_cdr(record, TICK_TYPE),
            )
        finally:
            with self._ledger.lock:
                self._ledger.queued_bytes -= sum(size for *_, size in tick.samples)
        # counted only once the tick record is written: before it, the samples are unreadable
        with self._ledger.lock:
            for (provider, *_), flag, size, seconds in zip(
                tick.samples, stored, sizes, spent, strict=True
            ):
                stats = provider.stats
                stats.count_stored += 1
                stats.bytes_written += size
                stats.write_seconds += seconds
                stats.baseline_samples += 1 - flag
                if stats.first_time_ns is None:
                    stats.first_time_ns = tick.time_ns
                stats.last_time_ns = tick.time_ns
