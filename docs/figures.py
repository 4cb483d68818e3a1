"""Draw the pictures of docs/parallel-mechanisms.md (run from the repository root):

    python docs/figures.py

leg-shapes.png: one leg of each shape with its joint names; library.png: every scenario of
the library at its home pose (`clearance draw FILE` draws one).
"""

from __future__ import annotations

from pathlib import Path

import clearance as cl
from clearance.plot.sketch import sketch
from clearance.scenario import build_mechanisms, library, library_path, load_scenario

HERE = Path(__file__).parent / "img"


def _rod(length: float, mass: float = 1.0) -> cl.Link:
    j = mass * length * length / 12.0
    return cl.Link(mass, (j, j, 1e-5), com=length / 2, length=length)


def leg_shapes() -> None:
    plat = cl.Platform(1.0, (0.01, 0.01, 0.02), position=(0.0, 0.0, 0.5))
    car = cl.Link(1.0, (0.01, 0.01, 0.01))
    shapes = [
        (
            "UPS: P in the middle (lower, upper)",
            cl.Leg("UPS", (0.3, 0, 0), (0.1, 0, 0), (_rod(0.4), _rod(0.4))),
        ),
        (
            "PRS: carriage on a rail (slider, rod)",
            cl.Leg("PRS", (0.3, 0, 0), (0.1, 0, 0), (car, _rod(0.45))),
        ),
        (
            "RSS + parallelogram: crank (crank, rod_a, rod_b)",
            cl.Leg("RSS", (0.3, 0, 0.6), (0.1, 0, 0), (_rod(0.2), _rod(0.4)), parallelogram=0.08),
        ),
        (
            "CU: 2 joints, sliding base (link)",
            cl.Leg("CU", (0, 0, 0), (0, 0, 0), (_rod(0.8),), actuated=None),
        ),
    ]
    mechs = []
    for title, leg in shapes:
        pm = cl.ParallelMechanism(title, plat, (leg,))
        mechs.append(pm.build(check=False))
    sketch(mechs, labels=True, columns=2).savefig(HERE / "leg-shapes.png", dpi=90)


def library_figure() -> None:
    mechs, titles = [], []
    for name in library():
        ideal, _, _ = build_mechanisms(load_scenario(library_path(name)))
        mechs.append(ideal)
        titles.append(name)
    sketch(mechs, titles=titles, columns=4).savefig(HERE / "library.png", dpi=70)


if __name__ == "__main__":
    HERE.mkdir(exist_ok=True)
    leg_shapes()
    library_figure()
