#!/usr/bin/env bash
# Checks every #include of engine/, viewer/, report/, cli/, tests/ and bench/ against the allowed directions
# (docs/ARCHITECTURE.md): an engine subsystem includes only itself and the subsystems below it,
# by their include roots ("core/image.h"), never by a relative path, never a GL or window
# header; report/ and viewer/ include the engine and themselves, cli/ all of them. The compiler enforces the same through the subsystems' include roots; this test also
# catches relative paths, which would bypass them.
# Usage: include_layers_test.sh SOURCE_DIR   (exit 1 and one line per violation when any)
#        include_layers_test.sh --self-test  (the check must catch planted violations)
set -uo pipefail

layers=(core scene trace methods eval present)

rank() {  # prints the layer index of a subsystem name, or nothing
  local i
  for i in "${!layers[@]}"; do [ "${layers[$i]}" = "$1" ] && echo "$i" && return; done
}

check_tree() {  # root -> prints violations, returns 1 when any
  local root=$1 bad=0 file line target where top own target_rank own_rank
  while IFS= read -r file; do
    where=${file#"$root"/}
    while IFS= read -r line; do
      target=$(sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]([^">]+)[">].*/\1/' <<<"$line")
      case "$line" in *'<'*'>'*) quoted=0 ;; *) quoted=1 ;; esac
      if [ $quoted -eq 0 ]; then
        if [[ $where == engine/* ]] && [[ $target =~ ^(GL/|GLFW/|EGL/|GLES|glad/|imgui|epoxy/) ]]; then
          echo "$where: includes <$target>: engine/ must not include GL or window headers"; bad=1
        fi
        continue
      fi
      if [[ $target == *..* ]] || [[ $target == engine/* ]]; then
        echo "$where: includes \"$target\": include by the subsystem's root (\"core/image.h\"), not a relative path"; bad=1
        continue
      fi
      top=${target%%/*}
      case "$where" in
        engine/*)
          own=$(cut -d/ -f2 <<<"$where")
          own_rank=$(rank "$own")
          target_rank=$(rank "$top")
          if [ -z "$own_rank" ]; then
            echo "$where: not inside a subsystem (${layers[*]})"; bad=1
          elif [ "$top" = viewer ]; then
            echo "$where: includes \"$target\": the engine never includes viewer/"; bad=1
          elif [ -z "$target_rank" ]; then
            [[ $target == */* ]] || continue  # a file beside it, e.g. network_kernel.inc
            echo "$where: includes \"$target\": not a subsystem"; bad=1
          elif [ "$target_rank" -gt "$own_rank" ]; then
            echo "$where: includes \"$target\": $own may not include $top, which is above it"; bad=1
          fi
          ;;
        report/*|viewer/*)
          own=${where%%/*}
          if [[ $top =~ ^(viewer|report|cli)$ ]] && [ "$top" != "$own" ]; then
            echo "$where: includes \"$target\": $own/ includes the engine and itself only"; bad=1
          fi
          ;;
      esac
    done < <(grep -E '^[[:space:]]*#[[:space:]]*include' "$file")
  done < <(find "$root/engine" "$root/viewer" "$root/report" "$root/cli" "$root/tests" "$root/bench" -type f \
             \( -name '*.h' -o -name '*.cpp' -o -name '*.inc' \) 2>/dev/null | sort)
  return $bad
}

if [ "${1:-}" = "--self-test" ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  mkdir -p "$tmp/engine/core" "$tmp/engine/methods" "$tmp/viewer/app" "$tmp/report" "$tmp/tests"
  printf '#include "core/image.h"\n#include <vector>\n' >"$tmp/engine/methods/fine.cpp"
  check_tree "$tmp" >/dev/null || { echo "self-test: a clean tree was refused"; exit 1; }
  cases=('engine/core/up.h|#include "methods/session.h"'
         'engine/core/rel.h|#include "../methods/session.h"'
         'engine/core/gl.h|#include <GL/gl.h>'
         'engine/core/old.h|#include "engine/core/image.h"'
         'engine/core/ui.h|#include "viewer/app/view_app.h"'
         'viewer/app/cli.h|#include "cli/commands.h"'
         'viewer/app/rep.h|#include "report/report.h"'
         'report/ui.h|#include "viewer/app/view_app.h"')
  for c in "${cases[@]}"; do
    f=${c%%|*}
    printf '%s\n' "${c#*|}" >"$tmp/$f"
    if check_tree "$tmp" >/dev/null; then echo "self-test: missed $f (${c#*|})"; exit 1; fi
    rm "$tmp/$f"
  done
  echo "self-test: ${#cases[@]} planted violations caught"
  exit 0
fi

[ $# -eq 1 ] || { echo "usage: $0 SOURCE_DIR | --self-test" >&2; exit 2; }
if check_tree "$1"; then
  echo "include layers: every #include goes down the layers (${layers[*]})"
else
  exit 1
fi
