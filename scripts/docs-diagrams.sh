#!/usr/bin/env bash
# Renders the diagrams in docs/ from their sources (Graphviz): docs/architecture/layers.dot -> .svg.
# Run after editing a .dot file and commit both.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v dot >/dev/null || scripts/install-deps.sh build graphviz
for source in docs/architecture/*.dot; do
  dot -Tsvg "$source" -o "${source%.dot}.svg"
done
