#!/usr/bin/env bash
# Run the test suite (or the pytest arguments given) where nothing but its temporary folders can
# be written, to find tests that write into the checkout, into ~ or elsewhere (docs/testing.md,
# "Only temporary folders"):
#
#   tools/read-only-suite.sh                        # the whole suite, one process
#   tools/read-only-suite.sh -n 2 --dist loadfile   # as `make test` runs it
#   tools/read-only-suite.sh tests/symbolic -m "not slow"
#
# HOME, TMPDIR and pytest's --basetemp point into one fresh scratch folder, the only place (with
# /dev/shm, /proc and /sys) left writable:
# - as root with mount namespaces (CI's containers, most Linux machines): the whole file system
#   is remounted read-only in a private mount namespace (the checkout itself, the virtualenv,
#   the real home, /tmp) and the scratch folder bound over itself, writable. Root ignores file
#   permissions but not a read-only mount.
# - otherwise the checkout is copied into the scratch folder, `chmod -R a-w`, and run from there
#   (imports from the copy first), as root under the unprivileged user nobody (setpriv): writes
#   into the checkout or ~ fail; writes to /tmp do not. Its files are also compared before and
#   after (all that is left as root where neither namespaces nor nobody work).
# (READ_ONLY_COPY=1 forces the second way.) A test that writes elsewhere fails ("Read-only file system", "Permission denied"); what was
# written into the temporary HOME, which no test should touch (those that run something that
# writes to ~ point HOME into their tmp_path), is listed and fails the check too.
set -uo pipefail
cd "$(dirname "$0")/.."
checkout=$PWD
if [[ -z "${PYTHON:-}" ]]; then
    if [[ -x .venv/bin/python ]]; then PYTHON=$checkout/.venv/bin/python; else PYTHON=$(command -v python3); fi
fi
[[ $# -gt 0 ]] || set -- -q

# Short names: Ray's socket paths under TMPDIR must stay within 107 bytes.
scratch=$(mktemp -d /tmp/ro.XXXXXX)
mkdir -p "$scratch/home" "$scratch/t"
export HOME=$scratch/home TMPDIR=$scratch/t
pytest=("$PYTHON" -m pytest -p no:cacheprovider --basetemp="$scratch/basetemp")

# Each way is tried on a probe first: a container may refuse mount namespaces, or nobody may
# not reach the virtualenv; the last way left, as root, only compares the checkout's files.
namespace() {  # COMMAND...: run it with the whole file system read-only but $scratch
    # shellcheck disable=SC2016  # expanded by the inner shell
    unshare -m --propagation private bash -c '
        set -e
        scratch=$1; shift
        mount --bind "$scratch" "$scratch"
        mount -o remount,bind,ro /
        exec "$@"' bash "$scratch" "$@"
}
as_nobody=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
if [[ $(id -u) -eq 0 && -z "${READ_ONLY_COPY:-}" ]] && namespace "$PYTHON" -c "" 2>/dev/null; then
    how="the whole file system read-only but $scratch (a private mount namespace)"
    echo "read-only-suite: $how" >&2
    namespace "${pytest[@]}" "$@"
    status=$?
else
    mkdir "$scratch/checkout"
    tar -C "$checkout" --exclude=./.venv --exclude=./.git --exclude='*/__pycache__' --exclude=./out -cf - . \
        | tar -C "$scratch/checkout" -xf -
    chmod -R a-w "$scratch/checkout"
    as=()
    if [[ $(id -u) -eq 0 ]]; then  # root writes anywhere: run as nobody, if nobody can run Python here
        chown nobody:nogroup "$scratch" "$scratch/home" "$scratch/t"  # not the copy
        if (cd "$scratch/checkout" && "${as_nobody[@]}" "$PYTHON" -c "") 2>/dev/null; then
            as=("${as_nobody[@]}")
        fi
    fi
    if [[ $(id -u) -ne 0 || ${#as[@]} -gt 0 ]]; then
        how="a read-only copy of the checkout ($scratch/checkout)${as:+, as nobody}"
    else
        how="a copy of the checkout, as root (no mount namespace, nobody cannot run $PYTHON): only its files compared"
    fi
    echo "read-only-suite: $how" >&2
    listing() { (cd "$scratch/checkout" && find . -path ./.pytest_cache -prune -o -name __pycache__ -prune -o -printf '%p %s %T@\n' | sort); }
    before=$(listing)
    (cd "$scratch/checkout" && PYTHONPATH="$scratch/checkout${PYTHONPATH:+:$PYTHONPATH}" "${as[@]}" "${pytest[@]}" "$@")
    status=$?
    changed=$(diff <(echo "$before") <(listing) | grep '^[<>]')
    if [[ -n "$changed" ]]; then
        echo "read-only-suite: the tests changed the checkout (< before, > after):" >&2
        echo "$changed" | head -50 >&2
        [[ $status -ne 0 ]] || status=1
    fi
fi

written=$(cd "$HOME" && find . -mindepth 1 | sort)
if [[ -n "$written" ]]; then
    echo "read-only-suite: the tests wrote into HOME ($HOME):" >&2
    echo "$written" | head -50 >&2
    [[ $status -ne 0 ]] || status=1
fi
if [[ $status -eq 0 ]]; then
    echo "read-only-suite: nothing written outside the temporary folders ($how)" >&2
    chmod -R u+w "$scratch" 2>/dev/null
    rm -rf "$scratch"
else
    echo "read-only-suite: exit $status; the scratch folder is kept: $scratch" >&2
fi
exit $status
