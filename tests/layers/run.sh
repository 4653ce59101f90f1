#!/usr/bin/env bash
# scripts/check-layers fails when a lower layer includes a higher one, and
# when the library includes a forwarding header at an old path: checked on a
# copy of the tree with one such include added, then the other.
set -euo pipefail
src=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
copy() {
  rm -rf "$work/tree" && mkdir -p "$work/tree/scripts"
  cp -r "$src/include" "$src/src" "$src/models" "$work/tree/"
  cp "$src/scripts/check-layers" "$work/tree/scripts/"
}
expect_failure() {  # $1: file, $2: include line, $3: the message expected
  copy
  printf '%s\n' "$2" >> "$work/tree/$1"
  set +e
  out=$("$work/tree/scripts/check-layers" "$work/tree")
  rc=$?
  set -e
  if [ "$rc" != 1 ]; then echo "layers: exit $rc, not 1, for $2 in $1"; echo "$out"; exit 1; fi
  if ! grep -qF -- "$3" <<<"$out"; then echo "layers: no '$3' in:"; echo "$out"; exit 1; fi
}
copy
"$work/tree/scripts/check-layers" "$work/tree" | grep -q "keep to the layer order"
expect_failure include/lagrangian/mechanics/dynamics.hpp '#include "lagrangian/scene/scene.hpp"' \
  "include/lagrangian/mechanics/dynamics.hpp:"
expect_failure include/lagrangian/mechanics/dynamics.hpp '#include "lagrangian/scene/scene.hpp"' \
  "layer 'mechanics' includes lagrangian/scene/scene.hpp of the higher layer 'scene'"
expect_failure src/integrate/run.cpp '#include <lagrangian/analysis/modes.hpp>' \
  "layer 'integrate' includes lagrangian/analysis/modes.hpp of the higher layer 'analysis'"
expect_failure include/lagrangian/ad/jet.hpp '#include "lagrangian/model.hpp"' \
  "layer 'ad' includes lagrangian/model.hpp of the higher layer 'core'"
expect_failure src/scene/run_scene.cpp '#include "lagrangian/simulate.hpp"' \
  "includes the old path lagrangian/simulate.hpp (a forwarding header)"
expect_failure src/analysis/bvp.cpp '#include "lagrangian/lagrangian.hpp"' \
  "layer 'analysis' includes the umbrella lagrangian/lagrangian.hpp"
echo "layers: all passed"
