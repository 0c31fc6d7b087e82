#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# birdcage(7) and README.md name every model and every conf key the built backend declares, so
# neither drifts from the code. The backend's own tables are read through the stock
# rotctl: `-l` for the models, `-L` for the conf keys (minus the ones Hamlib's serial frontend
# adds to every model, taken from a stock serial rotator).
#   man_matches_backend.sh ROTCTL BACKEND_SO MANPAGE README
# BIRDCAGE_PRELOAD_FIRST: a library preloaded ahead of the backend (the sanitizer runtime of a
# sanitized build).
set -uo pipefail
rotctl=$1 manpage=$3 readme=$4
backend=${BIRDCAGE_PRELOAD_FIRST:+$BIRDCAGE_PRELOAD_FIRST:}$2
conf_keys() { "$rotctl" "$@" -r /nonexistent -L 2>/dev/null | sed -n 's/^\([a-z_0-9]*\): ".*/\1/p' | sort -u; }

models=$(LD_PRELOAD=$backend "$rotctl" -l | awk '/Winegard/ {print $1}')
frontend=$(conf_keys -m 202)    # Easycomm II: a stock serial rotator with no keys of its own
backend_keys=$(comm -23 <(LD_PRELOAD=$backend conf_keys -m 90105) <(echo "$frontend"))
[[ -n $models && -n $backend_keys ]] || { echo "FAIL: could not read the backend's models or conf keys"; exit 1; }

failed=0
for model in $models; do
    grep -q "^\.B $model\$" "$manpage" || { echo "FAIL: model $model missing from $(basename "$manpage")"; failed=1; }
    grep -q "^| $model |" "$readme" || { echo "FAIL: model $model missing from README.md's table"; failed=1; }
done
for key in $backend_keys; do
    grep -Eq "^\.BR? (.*[ \"])?$key( |\$|\")" "$manpage" || { echo "FAIL: conf key $key missing from $(basename "$manpage")"; failed=1; }
    grep -q "\`$key\`" "$readme" || { echo "FAIL: conf key $key missing from README.md"; failed=1; }
done
((failed == 0)) && echo "ok: models $(echo $models) and conf keys $(echo $backend_keys) documented"
exit "$failed"
