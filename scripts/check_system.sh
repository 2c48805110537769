#!/bin/sh
# Check, before anything is downloaded, that this machine has what `make` builds the venv with:
# Python 3.10 or later with its venv module and headers, and C and C++ compilers (cmake, from
# pip, builds the interface packages the ROS wheels lack). Silent when all is there; otherwise
# one line naming every system package missing and the one command that installs them, exit 2.
#
#   scripts/check_system.sh [--packages]
#
# --packages prints the system packages this distribution needs (all of them, missing or not)
# and exits: scripts/setup_system.sh installs those. PYTHON3, CC and CXX name the interpreter
# and compilers to check (defaults python3, cc, c++: what python3 -m venv and cmake take).
python=${PYTHON3:-python3}
cc=${CC:-cc}
cxx=${CXX:-c++}

# The distribution's family, from os-release: its package manager and its packages' names.
family=other
if [ -r /etc/os-release ]; then
    # shellcheck disable=SC1091
    ids=$(. /etc/os-release && echo "$ID $ID_LIKE")
    case " $ids " in
        *' debian '* | *' ubuntu '*) family=debian ;;
        *' fedora '* | *' rhel '* | *' centos '*) family=fedora ;;
        *' suse '* | *' opensuse '*) family=suse ;;
        *' arch '*) family=arch ;;
    esac
fi

# package_for THING: the package that gives THING (python, venv, headers, cc, c++) here.
package_for() {
    case $family:$1 in
        debian:python) echo python3 ;;
        debian:venv) echo python3-venv ;;
        debian:headers) echo python3-dev ;;
        debian:cc) echo gcc ;;
        debian:c++) echo g++ ;;
        fedora:python | suse:python) echo python3 ;;
        fedora:venv | suse:venv) echo python3 ;;
        fedora:headers | suse:headers) echo python3-devel ;;
        fedora:cc | suse:cc) echo gcc ;;
        fedora:c++ | suse:c++) echo gcc-c++ ;;
        arch:python | arch:venv | arch:headers) echo python ;;
        arch:cc | arch:c++) echo gcc ;;
        *:python) echo 'Python 3.10+' ;;
        *:venv) echo "Python's venv module" ;;
        *:headers) echo "Python's headers (Python.h)" ;;
        *:cc) echo 'a C compiler' ;;
        *:c++) echo 'a C++ compiler' ;;
    esac
}

install_command() {
    sudo=
    [ "$(id -u)" = 0 ] || sudo='sudo '
    case $family in
        debian) echo "${sudo}apt-get install --no-install-recommends $*" ;;
        fedora) echo "${sudo}dnf install $*" ;;
        suse) echo "${sudo}zypper install $*" ;;
        arch) echo "${sudo}pacman -S --needed $*" ;;
        *) echo "your system's package manager: $*" ;;
    esac
}

# Each package once, in the order first named.
add() {
    case " $packages " in
        *" $1 "*) ;;
        *) packages="${packages:+$packages }$1" ;;
    esac
}

if [ "${1:-}" = --packages ]; then
    packages=
    for thing in python venv headers cc c++; do
        add "$(package_for $thing)"
    done
    echo "$packages"
    exit 0
fi

packages=
if ! "$python" -c 'import sys; sys.exit(sys.version_info < (3, 10))' 2>/dev/null; then
    add "$(package_for python)"
else
    # Debian's python3 leaves out ensurepip, without which python3 -m venv makes a venv with no
    # pip; its headers come apart too (cmake: "Could NOT find Python3 (missing: ...)").
    "$python" -c 'import ensurepip, venv' 2>/dev/null || add "$(package_for venv)"
    "$python" -c 'import os, sys, sysconfig
sys.exit(not os.path.isfile(os.path.join(sysconfig.get_path("include"), "Python.h")))' \
        2>/dev/null || add "$(package_for headers)"
fi
command -v "$cc" >/dev/null 2>&1 || add "$(package_for cc)"
command -v "$cxx" >/dev/null 2>&1 || add "$(package_for c++)"
[ -z "$packages" ] && exit 0
echo "make: this machine lacks what the install builds with: $packages; install with" \
    "\`$(install_command "$packages")\` and run make again" >&2
exit 2
