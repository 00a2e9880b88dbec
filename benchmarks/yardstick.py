"""The machine yardstick printed beside timings: seconds for 200 complex64 3-D FFTs of shape
(2, 64, 64, 64) over the last three axes on 2 threads, median of 3 runs. A timing divided by it
(measured in the same run) compares across machines and loads.

    python -m benchmarks.yardstick
"""

from __future__ import annotations

import statistics
import time


def yardstick_s(runs: int = 3) -> float:
    import numpy as np
    import scipy.fft

    x = (np.random.default_rng(0).standard_normal((2, 64, 64, 64)) + 0j).astype(np.complex64)
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        for _ in range(200):
            scipy.fft.fftn(x, axes=(1, 2, 3), workers=2)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


if __name__ == "__main__":
    print(f"{yardstick_s():.4f}")
