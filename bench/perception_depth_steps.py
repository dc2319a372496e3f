"""How coarse each tuned-on scan's depths are, and what the fit's thresholds make of it.

For every real scan tuned on (the held-out ones, ``"held_out": true`` in truth.json, are never
loaded), and for each band of range (0.5 m wide) holding at least 500 valid pixels, one line
with:

- ``step``: the sensor's depth step there, the median gap between the distinct depths the image
  holds in that band (a Kinect's disparity comes in whole steps, so its depths do too, and every
  step appears on a frame's many pixels; a sensor without steps shows its storage unit);
- ``step/z²``: the step over the band's middle range squared (a disparity step grows with the
  square of the range, so this is constant on a Kinect);
- ``noise``: the depth noise the chain measures there, ``sigma_1m · z²``
  (:func:`shapes.segment.survey`'s ``sigma_1m``), and the selection threshold ``T`` the fit gets
  (:meth:`shapes.fit.FitParams.for_noise`: ``noise_factor`` times the noise, at least its 8 mm
  default), with ``T/step``: how many depth steps the threshold spans.

Run from the repository root (a few seconds)::

    PYTHONPATH=. .venv/bin/python bench/perception_depth_steps.py
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import json  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from shapes import PerceptionParams, open_source  # noqa: E402
from shapes.segment import survey  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

BAND_M = 0.5
MIN_PIXELS = 500


bench = load_script(Path(__file__).with_name("perception.py"), "perception_bench")


def depth_step_m(depths: np.ndarray) -> float:
    """The median gap between the distinct values of ``depths`` (metres); 0 for fewer than two.

    >>> depth_step_m(np.array([1.0, 1.0, 1.01, 1.02, 1.02, 1.03]))
    0.01
    """
    distinct = np.unique(depths)
    return round(float(np.median(np.diff(distinct))), 9) if len(distinct) > 1 else 0.0


def main() -> None:
    truth = json.loads((bench.REAL_SCANS / "truth.json").read_text())
    params = PerceptionParams()
    print(
        f"{'scan':30} {'range m':>9} {'pixels':>7} {'step mm':>8} {'step/z² mm':>10} "
        f"{'noise mm':>8} {'T mm':>6} {'T/step':>6}"
    )
    for scan, measured in bench.REAL_TRUTH.items():
        if truth[measured].get("held_out"):
            continue  # never loaded
        frame = next(open_source(bench.REAL_SCANS / f"{scan}.npz"))
        sigma_1m = survey(frame, params.segmentation, 0).sigma_1m
        z = frame.points[:, 2]
        z = z[np.isfinite(z) & (z > 0)]
        for low in np.arange(0.0, float(z.max()), BAND_M):
            band = z[(z >= low) & (z < low + BAND_M)]
            if len(band) < MIN_PIXELS:
                continue
            mid = low + BAND_M / 2
            step = depth_step_m(band)
            noise = sigma_1m * mid**2
            threshold = params.fit.for_noise(noise).selection_threshold_m
            print(
                f"{scan:30} {low:4.1f}-{low + BAND_M:3.1f} {len(band):7d} {1000 * step:8.2f} "
                f"{1000 * step / mid**2:10.2f} {1000 * noise:8.2f} {1000 * threshold:6.1f} "
                f"{threshold / step if step else float('inf'):6.2f}"
            )


if __name__ == "__main__":
    main()
