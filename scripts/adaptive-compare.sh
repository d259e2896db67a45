#!/bin/sh
# Adaptive clearing against an offset pocket on the same parts (islands, L, neck, circle):
# planner time, peak and mean engagement as the independent walk over the written program
# measures them (oficina_sim::engagement), and the length cut. Prints a Markdown table.
set -e
cd "$(dirname "$0")/.."
cargo test -q -p oficina-app --test adaptive adaptive_against_an_offset_pocket -- --nocapture 2>&1 | grep '^|'
