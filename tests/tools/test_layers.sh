#!/usr/bin/env bash
# The runtime's folders are layers (docs/architecture.md): a header or source in one folder
# includes only folders before it in the order below — the model description below the
# integrators, the drivers above them. A folder that includes one after it is a cycle waiting
# to happen (the bounce constraint_projection → lagrangian_midpoint → … this order removed).
#   usage: test_layers.sh SOURCE_DIR
set -u
src=$1
. "$(dirname "$0")/check.sh"
order=(core particles rigid system integrators collision contact view simulate)
rank() { local i; for i in "${!order[@]}"; do [ "${order[$i]}" = "$1" ] && { echo "$i"; return; }; done; echo -1; }
files=0
for root in "$src/runtime/include/phynjo/runtime" "$src/runtime/src"; do
  for dir in "$root"/*/; do
    folder=$(basename "$dir")
    [ -n "$(find "$dir" -name '*.[ch]pp' -print -quit)" ] || continue # a folder git does not hold (left empty)
    r=$(rank "$folder")
    [ "$r" -lt 0 ] && { bad "$folder: a runtime folder missing from the layer order"; continue; }
    while IFS= read -r f; do
      files=$((files + 1))
      while IFS= read -r inc; do
        to=$(rank "$inc")
        if [ "$to" -gt "$r" ]; then bad "${f#$src/} includes $inc/, a layer above $folder/"; fi
      done < <(sed -n 's|^#include "phynjo/runtime/\([a-z_]*\)/.*|\1|p' "$f")
    done < <(find "$dir" -name '*.[ch]pp')
  done
done
[ "$files" -gt 50 ] && ok "$files runtime files read, each including only its layer and those below" || bad "only $files files read"
finish
