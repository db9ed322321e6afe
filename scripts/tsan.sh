#!/usr/bin/env bash
# The viewer's window test once under ThreadSanitizer (build-tsan/): the UI thread against
# the render session's worker (snapshots, inspection, restarts on camera moves, pause and
# step), driven by scripted input under Xvfb. The session runs one render thread
# (--threads 1): oneTBB's scheduler is not built with TSan, so tasks handed between its
# worker threads would be reported as races TSan cannot see the synchronisation of; with
# one thread the arena has no workers. Mesa's rasteriser threads are suppressed in
# tests/tsan.supp for the same reason. Any report in Penumbra's own code fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --no-build
source scripts/sanitized_build.sh
sanitized_build build-tsan thread penumbra
export TSAN_OPTIONS="halt_on_error=1:exitcode=66:second_deadlock_stack=1:suppressions=$PWD/tests/tsan.supp"
bash tests/viewer/app/window_test.sh "$PWD/build-tsan/penumbra" "$PWD" "$PWD/build-tsan/window" --threads 1
