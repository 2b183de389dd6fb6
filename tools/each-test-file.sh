#!/usr/bin/env bash
# Run every test file on its own, as `pytest FILE` from the checkout's root, slow tests included,
# in file order (-p no:randomly), and list the files that fail alone: a file that passes only
# after another has run depends on that one's leftovers (a fixture, an import, a registration).
#
#   tools/each-test-file.sh                 # every tests/**/test_*.py and examples/**/test_*.py
#   tools/each-test-file.sh tests/tasks     # the files under some folders (or single files)
#   PYTEST="python -P -m pytest" tools/each-test-file.sh
#
# Runs pytest's own entry point (`.venv/bin/pytest` when there is one), never `python -m pytest`,
# which puts the current folder on sys.path and so hides a file that imports `tests.x`. Each
# file's output goes to $LOGS (a temporary folder by default); the last lines list the failures
# and the exit status is 1 when any file failed.
set -uo pipefail
cd "$(dirname "$0")/.."

if [[ -z "${PYTEST:-}" ]]; then
    if [[ -x .venv/bin/pytest ]]; then PYTEST=.venv/bin/pytest; else PYTEST=pytest; fi
fi
LOGS=${LOGS:-$(mktemp -d -t each-test-file.XXXXXX)}
mkdir -p "$LOGS"

[[ $# -gt 0 ]] || set -- tests examples
mapfile -t files < <(find "$@" -name 'test_*.py' -not -path '*/__pycache__/*' | sort)
if [[ ${#files[@]} -eq 0 ]]; then
    echo "each-test-file: no test_*.py under $*" >&2
    exit 2
fi

failed=()
start_all=$SECONDS
for file in "${files[@]}"; do
    log="$LOGS/$(echo "$file" | tr / _).log"
    start=$SECONDS
    # shellcheck disable=SC2086  # PYTEST may be a command with arguments
    $PYTEST "$file" -p no:randomly -p no:cacheprovider -q >"$log" 2>&1
    status=$?
    summary=$(tail -n 1 "$log")
    if [[ $status -eq 0 ]]; then
        printf 'ok    %4ds  %s  (%s)\n' $((SECONDS - start)) "$file" "$summary"
    else
        printf 'FAIL  %4ds  %s  (exit %d: %s; log %s)\n' $((SECONDS - start)) "$file" "$status" "$summary" "$log"
        failed+=("$file")
    fi
done

echo "${#files[@]} files in $((SECONDS - start_all)) s; ${#failed[@]} failed alone"
for file in "${failed[@]}"; do echo "failed alone: $file"; done
[[ ${#failed[@]} -eq 0 ]]
