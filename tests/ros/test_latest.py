"""The perception subscriber's mailbox: a slow consumer gets the newest cloud, no backlog."""

import threading
import time

from api.ros.latest import Latest


def test_a_slow_consumer_takes_the_newest_items_and_the_rest_are_counted_as_replaced() -> None:
    box: Latest[int] = Latest()
    taken: list[int] = []

    def consume() -> None:
        while (item := box.take()) is not None:
            taken.append(item)
            time.sleep(0.01)  # slower than the producer

    consumer = threading.Thread(target=consume)
    consumer.start()
    for item in range(200):
        box.put(item)
        time.sleep(0.0005)
    deadline = time.monotonic() + 30
    while 199 not in taken and time.monotonic() < deadline:  # the newest is never lost
        time.sleep(0.01)
    box.close()
    consumer.join(5)
    assert not consumer.is_alive()
    assert taken == sorted(taken)  # in order, none twice
    assert taken[-1] == 199
    assert len(taken) + box.replaced == 200
    assert box.replaced > 0


def test_take_after_close_returns_none_even_with_an_item_waiting() -> None:
    box: Latest[str] = Latest()
    box.put("cloud")
    box.close()
    assert box.take() is None
