#!/usr/bin/env bash
# Build the interface packages of interfaces/ into a virtual environment, each only when needed:
# skipped when it imports already without having been built here (a ROS installation provides
# it), skipped when built here from the same sources, restored from the machine's cache when
# built before from the same sources for the same Python and ROS wheels, built otherwise (all
# packages at once, C and Python type supports only unless WITH_CPP_TYPESUPPORT=ON). A build's
# output is kept in a log shown only if it fails.
#
#   scripts/build_interfaces.sh VENV [INTERFACES_DIR]
#
# The cache is $SIMPLE_ROBOT_CONTROL_CACHE (default ~/.cache/simple_robot_control)/interfaces;
# INTERFACES_CACHE=off skips it, `make clean-cache` empties it.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
venv=$(cd "${1:?usage: build_interfaces.sh VENV [INTERFACES_DIR]}" && pwd)
sources=$(cd "${2:-$here/../interfaces}" && pwd)
python=$venv/bin/python
with_cpp=${WITH_CPP_TYPESUPPORT:-OFF}
cache=${SIMPLE_ROBOT_CONTROL_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/simple_robot_control}/interfaces
[ "${INTERFACES_CACHE:-on}" != off ] || cache=

# What the built libraries depend on besides their sources: this Python and the ROS wheels
# they link against (the build tools are not among them).
runtime=$("$python" - <<'PYTHON'
import importlib.metadata
import sys
names = ('ros-jazzy-rclpy', 'ros-jazzy-rosidl-runtime-c', 'ros-jazzy-rosidl-typesupport-c',
         'ros-jazzy-rosidl-typesupport-fastrtps-c', 'ros-jazzy-rosidl-typesupport-introspection-c',
         'ros-jazzy-std-msgs', 'ros-jazzy-geometry-msgs', 'ros-jazzy-action-msgs',
         'ros-jazzy-builtin-interfaces', 'numpy')
versions = []
for name in names:
    try:
        versions.append(f'{name}=={importlib.metadata.version(name)}')
    except importlib.metadata.PackageNotFoundError:
        versions.append(f'{name} absent')
print(sys.version.split()[0], *versions)
PYTHON
)

digest_of() {
    {
        (cd "$sources" && find "$1" cmake -type f -print0 | sort -z | xargs -0 sha256sum)
        echo "$runtime cpp=$with_cpp"
    } | sha256sum | cut -c1-16
}

prepare_tools() {
    "$python" -m pip --disable-pip-version-check install --quiet \
        -r "$here/../requirements/interfaces.txt" 2> >(grep -v 'is ignored' >&2)
    if ! command -v cmake > /dev/null; then
        "$python" -m pip --disable-pip-version-check install --quiet 'cmake>=3.21,<4' \
            2> >(grep -v 'is ignored' >&2)
    fi
}

# Install a build from the cache: its files name the prefix it was built for, the stored one.
restore() {
    local name=$1 archive=$2 built_for
    built_for=$(tar -xzf "$archive" -O ./.built_for)
    tar -xzf "$archive" -C "$venv" --exclude ./.built_for
    if [ "$built_for" != "$venv" ]; then
        tar -tzf "$archive" | grep -v '/$' | (cd "$venv" && xargs -d '\n' grep -lsF "$built_for" || true) |
            (cd "$venv" && xargs -r -d '\n' sed -i "s|$built_for|$venv|g")
    fi
}

build() {
    local name=$1 digest=$2 work
    work=$(mktemp -d)
    trap 'rm -rf "$work"' RETURN
    if ! (
        export AMENT_PREFIX_PATH=$venv PATH=$venv/bin:$PATH
        cmake -S "$sources/$name" -B "$work/build" -DCMAKE_INSTALL_PREFIX="$venv" \
            -DCMAKE_PREFIX_PATH="$venv" -DPython3_EXECUTABLE="$python" \
            -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DWITH_CPP_TYPESUPPORT="$with_cpp" &&
            cmake --build "$work/build" --parallel "$(nproc)" &&
            cmake --install "$work/build"
    ) > "$work/build.log" 2>&1; then
        echo "build_interfaces: building $name failed; the end of its log:" >&2
        tail -n 40 "$work/build.log" >&2
        return 1
    fi
    echo "$digest" > "$venv/share/$name/built_from_interfaces"
    if [ -n "$cache" ]; then
        echo "$venv" > "$work/.built_for"
        sed -e "s|^$venv/|./|" "$work/build/install_manifest.txt" | grep -v '__pycache__' \
            > "$work/files"
        echo "./share/$name/built_from_interfaces" >> "$work/files"
        mkdir -p "$cache"
        tar -czf "$cache/.$name-$digest.$$" -C "$venv" -T "$work/files" -C "$work" ./.built_for &&
            mv "$cache/.$name-$digest.$$" "$cache/$name-$digest.tar.gz"
    fi
}

to_build=()
for package_xml in "$sources"/*/package.xml; do
    name=$(basename "$(dirname "$package_xml")")
    digest=$(digest_of "$name")
    stamp=$venv/share/$name/built_from_interfaces
    if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$digest" ]; then
        echo "$name: up to date"
    elif [ ! -f "$stamp" ] && "$python" -c "import $name.msg" 2> /dev/null; then
        echo "$name: provided by this environment; not built"
    elif [ -n "$cache" ] && [ -f "$cache/$name-$digest.tar.gz" ]; then
        restore "$name" "$cache/$name-$digest.tar.gz"
        echo "$name: restored from $cache"
    else
        to_build+=("$name:$digest")
    fi
done
[ ${#to_build[@]} -gt 0 ] || exit 0
started=$SECONDS
prepare_tools
echo "build_interfaces: build tools installed in $((SECONDS - started)) s"
pids=()
for entry in "${to_build[@]}"; do
    (
        package_started=$SECONDS
        build "${entry%%:*}" "${entry#*:}"
        echo "${entry%%:*}: built into $venv in $((SECONDS - package_started)) s"
    ) &
    pids+=($!)
done
failed=0
for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
exit $failed
