#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Installs what birdcage needs from Debian's packages (bookworm). Idempotent: installs only what is
# missing. As root it runs apt-get; otherwise it prints the exact command to run and fails.
set -euo pipefail

packages=(
    build-essential cmake pkg-config
    libhamlib-dev libhamlib-utils   # headers + the stock rotctl/rotctld the tests and demo drive
    libserialport-dev
    libncurses-dev                  # birdcage-tui
    catch2
    python3                         # the doc check (tests/docs)
)
if [[ "${BIRDCAGE_SETUP_EXTRA:-}" != "" ]]; then
    read -r -a extra <<<"${BIRDCAGE_SETUP_EXTRA}"
    packages+=("${extra[@]}")
fi

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if ((${#missing[@]} == 0)); then
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    echo "setup: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    echo "setup: installing ${missing[*]} with sudo" >&2
    sudo DEBIAN_FRONTEND=noninteractive apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
    echo "setup: missing Debian packages. Run:" >&2
    echo "  sudo apt-get install ${missing[*]}" >&2
    exit 1
fi
