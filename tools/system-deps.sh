#!/usr/bin/env bash
# The system programs the tests drive, from Debian's packages: tmux (the shell's terminal
# session), chromium (the studio's browser tests) and neovim (the documented editor set-up).
# Installed only where missing and only as root (CI runs as root); elsewhere the tests that need
# them skip and say which package to install.
set -u
missing=()
command -v tmux >/dev/null 2>&1 || missing+=(tmux)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
command -v nvim >/dev/null 2>&1 || missing+=(neovim)
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1; then
  echo "note: ${missing[*]} not installed (apt-get install ${missing[*]}); the tests that need them skip" >&2
  exit 0
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null \
  || echo "note: apt-get could not install ${missing[*]}; the tests that need them skip" >&2
exit 0
