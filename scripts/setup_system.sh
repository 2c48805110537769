#!/bin/sh
# Install, as root, the system packages `make` builds with on a Debian or Ubuntu machine (the
# ones scripts/check_system.sh names), with git and make: the one set-up step of the container
# image (Dockerfile) and of `make fresh-linux`'s fresh root filesystems, which test it.
#
#   scripts/setup_system.sh
set -eu
[ $# = 0 ] || { echo 'usage: scripts/setup_system.sh (as root, no arguments)' >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
packages=$("$here/check_system.sh" --packages)
if [ "$(id -u)" != 0 ]; then
    echo "setup_system.sh: run it as root (sudo $0): it installs $packages" >&2
    exit 2
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "setup_system.sh: no apt-get here; install $packages, git and make with the system's" \
        'package manager' >&2
    exit 2
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
# shellcheck disable=SC2086
apt-get install -y -q --no-install-recommends ca-certificates git make $packages
