"""Python's time for 100 steps of 10 ms of the default pendulum (best of 5 fresh simulations;
set-up excluded), to compare with the bare stepper (`step_overhead.rs`)."""

import time

import pendulum_fem

best = float("inf")
for _ in range(5):
    sim = pendulum_fem.Simulation()
    start = time.perf_counter()
    for _ in range(100):
        sim.step(0.01)
    best = min(best, time.perf_counter() - start)
print(f"python: 100 x step(0.01): best {best:.4f} s ({best * 10:.3f} ms per step)")
