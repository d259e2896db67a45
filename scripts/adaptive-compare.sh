#!/bin/sh
# Adaptive clearing against an offset pocket and FreeCAD's adaptive (Path workbench,
# scripts/freecad-adaptive.py, when freecadcmd is installed) on the same parts (islands, L,
# neck, circle): planner time on the default profile, peak and mean engagement as the
# independent walk over each program read back measures them (oficina_sim::engagement).
# Prints a Markdown table.
set -e
cd "$(dirname "$0")/.."
cargo test -q -p oficina-app --test adaptive adaptive_against_an_offset_pocket_and_freecad -- --nocapture 2>&1 | grep '^|'
