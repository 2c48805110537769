#!/usr/bin/env bash
# Build the interface packages of interfaces/ into a virtual environment, each only when needed:
# skipped when it imports already without having been built here (a ROS installation provides
# it), skipped when built here from the same sources, built otherwise. The build's output is
# kept in a log shown only if the build fails.
#
#   scripts/build_interfaces.sh VENV [INTERFACES_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
venv=$(cd "${1:?usage: build_interfaces.sh VENV [INTERFACES_DIR]}" && pwd)
sources=$(cd "${2:-$here/../interfaces}" && pwd)
python=$venv/bin/python
tools_ready=

digest_of() {
    (cd "$sources" && find "$1" cmake -type f -print0 | sort -z | xargs -0 sha256sum) |
        sha256sum | cut -c1-16
}

prepare_tools() {
    [ -z "$tools_ready" ] || return 0
    "$python" -m pip --disable-pip-version-check install --quiet \
        -r "$here/../requirements/interfaces.txt" 2> >(grep -v 'is ignored' >&2)
    if ! command -v cmake > /dev/null; then
        "$python" -m pip --disable-pip-version-check install --quiet 'cmake>=3.21,<4' \
            2> >(grep -v 'is ignored' >&2)
    fi
    tools_ready=yes
}

build() {
    local name=$1 work
    work=$(mktemp -d)
    trap 'rm -rf "$work"' RETURN
    if ! (
        export AMENT_PREFIX_PATH=$venv PATH=$venv/bin:$PATH
        cmake -S "$sources/$name" -B "$work" -DCMAKE_INSTALL_PREFIX="$venv" \
            -DCMAKE_PREFIX_PATH="$venv" -DPython3_EXECUTABLE="$python" \
            -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF &&
            cmake --build "$work" --parallel "$(nproc)" &&
            cmake --install "$work"
    ) > "$work/build.log" 2>&1; then
        echo "build_interfaces: building $name failed; the end of its log:" >&2
        tail -n 40 "$work/build.log" >&2
        return 1
    fi
}

for package_xml in "$sources"/*/package.xml; do
    name=$(basename "$(dirname "$package_xml")")
    digest=$(digest_of "$name")
    stamp=$venv/share/$name/built_from_interfaces
    if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$digest" ]; then
        echo "$name: up to date"
        continue
    fi
    if [ ! -f "$stamp" ] && "$python" -c "import $name.msg" 2> /dev/null; then
        echo "$name: provided by this environment; not built"
        continue
    fi
    prepare_tools
    started=$SECONDS
    build "$name"
    echo "$digest" > "$stamp"
    echo "$name: built into $venv in $((SECONDS - started)) s"
done
