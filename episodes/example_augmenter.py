"""An example augmenter process: it asks the server for episodes that lack its augmentation,
derives data from their recorded frames, posts it back and completes the work.

It speaks only HTTP (``httpx``) and NumPy, as an augmenter written by someone else would::

    .venv/bin/python -m episodes.example_augmenter --url http://127.0.0.1:8000 \\
        --activity babbling --source icub/skin --augmentation skin_energy

For each claimed episode it replays the frames of ``--source`` (a float array), posts one
derived sample per frame, the array's energy (sum of squares) to channel ``<source>/energy``
linked to its source frame, sends a heartbeat every ``--batch`` frames, and completes the
claim, which ends the run. With ``--once`` it stops when there is no work; otherwise it waits
for new episodes (long-poll) until interrupted.
"""

import argparse
import base64
import json
from typing import Any

import httpx
import numpy as np

__all__ = ["augment_one", "main"]


def _array(value: dict[str, Any]) -> np.ndarray:
    raw = base64.b64decode(value["b64"])
    return np.frombuffer(raw, dtype=value["dtype"]).reshape(value["shape"])


def _value(array: np.ndarray) -> dict[str, Any]:
    data = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
    return {
        "dtype": data.dtype.name,
        "shape": list(data.shape),
        "b64": base64.b64encode(data.tobytes()).decode(),
    }


def augment_one(
    client: httpx.Client,
    *,
    activity: str,
    source: str,
    augmentation: str = "energy",
    worker: str = "example-augmenter",
    wait_s: float = 0.0,
    batch: int = 100,
) -> dict[str, Any] | None:
    """Claim one episode, augment it and complete the claim; the ended run, or ``None`` when
    there was no work."""
    answer = client.post(
        f"/augmentations/{augmentation}/claims",
        json={"worker": worker, "activity": activity, "wait_s": wait_s, "lease_s": 60},
    )
    answer.raise_for_status()
    if answer.status_code == 204:
        return None
    claim = answer.json()
    episode, run, token = claim["episode_id"], claim["run"]["id"], claim["token"]
    channel = f"{source}/energy"
    declared = {channel: {"kind": "float_array", "dtype": "float64", "shape": [1]}}
    pending: list[dict[str, Any]] = []

    def post() -> None:
        if pending:
            body = {"samples": pending, "channels": declared}
            client.post(f"/episodes/{episode}/runs/{run}/samples", json=body).raise_for_status()
            client.post(f"/augmentations/claims/{token}/heartbeat", json={"lease_s": 60})
            pending.clear()

    with client.stream(
        "GET", f"/episodes/{episode}/streams/replay", params={"channels": [source]}
    ) as frames:
        frames.raise_for_status()
        for line in frames.iter_lines():
            if not line:
                continue
            frame = json.loads(line)
            for sample in frame["samples"]:
                energy = float(np.sum(_array(sample["value"]).astype(np.float64) ** 2))
                pending.append(
                    {
                        "frame": frame["frame"],
                        "source_channel": source,
                        "derived_channel": channel,
                        "value": _value(np.array([energy])),
                    }
                )
            if len(pending) >= batch:
                post()
    post()
    done = client.post(f"/augmentations/claims/{token}/complete")
    done.raise_for_status()
    result: dict[str, Any] = done.json()
    return result


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--url", default="http://127.0.0.1:8000")
    parser.add_argument("--token", default=None, help="ENGRAM_TOKEN of the server, if any")
    parser.add_argument("--activity", required=True)
    parser.add_argument("--source", required=True, help="a float-array provider, e.g. icub/skin")
    parser.add_argument("--augmentation", default="energy")
    parser.add_argument("--worker", default="example-augmenter")
    parser.add_argument("--batch", type=int, default=100)
    parser.add_argument("--once", action="store_true", help="stop when there is no work")
    args = parser.parse_args(argv)
    headers = {"Authorization": f"Bearer {args.token}"} if args.token else {}
    with httpx.Client(base_url=args.url, headers=headers, timeout=120) as client:
        while True:
            run = augment_one(
                client,
                activity=args.activity,
                source=args.source,
                augmentation=args.augmentation,
                worker=args.worker,
                wait_s=0.0 if args.once else 30.0,
                batch=args.batch,
            )
            if run is not None:
                print(f"episode {run['episode_id']}: run {run['id']} v{run['version']} done")
            elif args.once:
                return


if __name__ == "__main__":
    main()
