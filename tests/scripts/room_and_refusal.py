"""Two calls that take the runner's other paths, on the device named on the command line
(``test_gpu.py`` runs it with ``cuda`` in numba's CUDA simulator and with ``cpu``, and
compares what it prints): a batch whose contact rows and pair rows outgrow a new world's
in the middle of a call (room made, the call made again), and a batch in which one world
leaves the envelope (the call refused, every world put back). Prints one JSON line."""

import hashlib
import json
import sys

import numpy as np

import impulse2d as p2


def digest(world: p2.World) -> str:
    arrays = world.state.arrays().values()
    return hashlib.sha256(b"".join(a.tobytes() for a in arrays)).hexdigest()[:16]


def main(device: str) -> None:
    stack = p2.World(batch_size=2, device=device)
    stack.add(p2.Plane(normal=(0, 1), point=(0, 0)))
    for i in range(12):
        stack.add(p2.Box(position=(1.2 * i, 0.6 + 0.05 * i), width=1.0, height=1.0, angle=0.1))
    stack.bodies[3].velocity = np.array([[0.0, 0.0], [2.0, 1.0]])
    rows = stack.state.contact_capacity, stack._runner.pair_capacity
    stack.step(1 / 60, steps=40)
    grown = stack.state.contact_capacity, stack._runner.pair_capacity

    pump = p2.World(gravity=(0.0, 0.0), batch_size=2, device=device)
    pump.add(p2.Plane(normal=(0, 1), point=(0, -1), restitution=0.0))
    pump.add(p2.Plane(normal=(0, -1), point=(0, 1), restitution=0.0))
    ball = pump.add(p2.Circle(radius=0.25, velocity=(0, 10), restitution=1.0))
    ball.restitution = np.array([1.0, 2.0])
    pump.step(1 / 60, steps=3)
    before = digest(pump)
    try:
        pump.step(1 / 60, steps=200)
        refused = None
    except p2.EnvelopeError as error:
        refused = [error.world, error.body, error.quantity]
    print(json.dumps({
        "device": stack.device, "rows": rows, "grown": grown, "stack": digest(stack),
        "refused": refused, "unchanged": digest(pump) == before, "pump": digest(pump),
    }))  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1])
