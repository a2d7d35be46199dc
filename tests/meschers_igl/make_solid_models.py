"""Write the study's artist-style solid models to meschers_igl/data/solids (run from the repo root).

python tests/meschers_igl/make_solid_models.py

The models are built here, the way the tests build them (half-spaces, welded quads), not by the
code under test; each OBJ gets a sidecar JSON with its view and the depth gap it hides.
"""

from __future__ import annotations

import json
from pathlib import Path

from relief_models import reutersvard_relief
from visible_models import (
    ISO_UP,
    ISO_VIEW,
    block_stairs,
    hidden_gap_cube,
    hidden_gap_frame,
    sheared_tribar_torus,
    u_tribar,
    write_obj,
)

OUT = Path(__file__).resolve().parents[2] / "meschers_igl" / "data" / "solids"
MODELS = {
    "u_tribar": (
        u_tribar,
        None,
        "A Penrose tribar as one closed U-shaped solid (sphere "
        "topology) whose two capped ends line up on screen.",
    ),
    "block_stairs": (block_stairs, None, "Penrose stairs as four separate closed blocks."),
    "hidden_gap_frame": (
        hidden_gap_frame,
        None,
        "A tribar frame broken behind a crossing bar "
        "(the gap is hidden; the pieces are bridged behind the occluder).",
    ),
    "hidden_gap_cube": (
        hidden_gap_cube,
        None,
        "The impossible cube as a real closed frame "
        "(genus 2) whose impossible bar is broken behind a crossing bar: the "
        "pieces line up on screen L sqrt(3) apart in depth; bridged behind the "
        "occluder, the frame closes into genus 3.",
    ),
    "sheared_tribar_torus": (
        sheared_tribar_torus,
        "manhattan",
        "A real closed torus sheared "
        "along the view: it looks like a tribar only to a person who "
        "assumes right angles (perceive='manhattan').",
    ),
    "reutersvard_relief": (
        reutersvard_relief,
        "manhattan",
        "Reutersvard's triangle of twelve "
        "touching cubes as a shallow relief: each cube sheared along the view "
        "and the depth compressed to 0.3, a real thin torus; a person "
        "assuming right angles sees cubes climbing sqrt(3) * 4 per turn "
        "(perceive='manhattan').",
    ),
}


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for name, (build, perceive, text) in MODELS.items():
        V, polys, gap = build()
        write_obj(OUT / f"{name}.obj", V, polys)
        meta = {
            "view": ISO_VIEW.tolist(),
            "up": ISO_UP.tolist(),
            "seen_as": "solid",
            "perceive": perceive,
            "depth_gap": float(gap),
            "description": text,
        }
        (OUT / f"{name}.json").write_text(json.dumps(meta, indent=1) + "\n")
        print(name, len(V), "vertices", len(polys), "polygons, gap", gap)


if __name__ == "__main__":
    main()
