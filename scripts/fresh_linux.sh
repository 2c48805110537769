#!/usr/bin/env bash
# make fresh-linux: the README's first commands on fresh root filesystems, as a newcomer runs
# them. For each distribution: a minimal root (debootstrap) with only what a newcomer brings
# (git, make, python3), this repository's HEAD cloned into it; then, in a chroot of its own
# (mount and PID namespaces; the host's network, for the downloads):
#   1. `make demo` must stop at once, before any download, with check_system.sh's one line;
#   2. a venv without pip is left where an earlier failure leaves one (make must make it again);
#   3. scripts/setup_system.sh (the container image's one set-up step) installs what was named;
#   4. `make demo` must print FINISHED.
# Each step's wall time is printed. Needs root and debootstrap; the roots are made under
# FRESH_ROOT (default /var/tmp) and removed at the end, whatever happened.
#
#   scripts/fresh_linux.sh [DISTRIBUTION ...]   (default: bookworm trixie)
#
# noble (Ubuntu 24.04) needs a debootstrap that knows it and Ubuntu's archive key
# (ubuntu-keyring): Debian 12's has neither.
set -euo pipefail
repository=$(cd "$(dirname "$0")/.." && pwd)
[ "$(id -u)" = 0 ] || { echo 'fresh_linux.sh: run it as root (debootstrap, chroot)' >&2; exit 2; }
command -v debootstrap >/dev/null || {
    echo 'fresh_linux.sh: needs debootstrap (apt-get install debootstrap)' >&2; exit 2; }
distributions=("$@")
[ ${#distributions[@]} -gt 0 ] || distributions=(bookworm trixie)
work=$(mktemp -d "${FRESH_ROOT:-/var/tmp}/simple_robot_control-fresh.XXXXXX")
trap 'rm -rf --one-file-system "$work"' EXIT

mirror_of() {
    case $1 in
        noble | jammy) echo http://archive.ubuntu.com/ubuntu ;;
        *) echo http://deb.debian.org/debian ;;
    esac
}

# A machine behind a TLS proxy (this one) trusts the proxy's certificate authority through
# SSL_CERT_FILE or PIP_CERT: the roots are given the same trust, and nothing else of its own.
trust=${PIP_CERT:-${SSL_CERT_FILE:-}}
trust_environment=()
[ -z "$trust" ] || trust_environment=(SSL_CERT_FILE=/etc/ssl/host-trust.pem
                                      PIP_CERT=/etc/ssl/host-trust.pem)

# In the root, as root, with a newcomer's environment (no pip configuration of this machine's).
in_root() {
    unshare --mount --pid --fork --propagation private bash -c '
        root=$1; shift
        mount -t proc proc "$root/proc"
        mount --rbind /dev "$root/dev"
        mount -t tmpfs -o mode=1777 tmpfs "$root/dev/shm"
        mount --rbind /sys "$root/sys"
        exec chroot "$root" env -i HOME=/root LANG=C.UTF-8 TERM=dumb \
            PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "$@"' \
        in_root "$root" "${trust_environment[@]}" "$@"
}

seconds_since() {
    echo $(( $(date +%s) - $1 ))
}

failed=()
for distribution in "${distributions[@]}"; do
    root=$work/$distribution
    keyring=()
    if [ "$(mirror_of "$distribution")" != "$(mirror_of bookworm)" ]; then
        keyring=(--keyring=/usr/share/keyrings/ubuntu-archive-keyring.gpg)
        [ -r "${keyring[0]#--keyring=}" ] || {
            echo "$distribution: FAIL: needs Ubuntu's archive key (apt-get install ubuntu-keyring)"
            failed+=("$distribution"); continue; }
    fi
    start=$(date +%s)
    if ! debootstrap "${keyring[@]}" --variant=minbase --include=git,make,python3,ca-certificates \
            "$distribution" "$root" "$(mirror_of "$distribution")" \
            > "$work/$distribution.log" 2>&1; then
        echo "$distribution: debootstrap failed (last lines below)"
        tail -n 5 "$work/$distribution.log"
        failed+=("$distribution")
        continue
    fi
    cp /etc/resolv.conf "$root/etc/resolv.conf"
    [ -z "$trust" ] || cp "$trust" "$root/etc/ssl/host-trust.pem"
    git clone --quiet --no-hardlinks "$repository" "$root/root/simple_robot_control"
    echo "$distribution: root filesystem in $(seconds_since "$start") s" \
        "($(in_root python3 --version))"

    # 1. The first make demo names what is missing, before anything is downloaded.
    start=$(date +%s)
    if in_root bash -c 'cd /root/simple_robot_control && make demo' > "$work/first.log" 2>&1; then
        echo "$distribution: FAIL: make demo went on without what it builds with"
        failed+=("$distribution")
        continue
    fi
    line=$(grep -m1 'this machine lacks' "$work/first.log" || true)
    if [ -z "$line" ] || [ -e "$root/root/simple_robot_control/.venv" ]; then
        echo "$distribution: FAIL: the first make demo did not stop naming what is missing:"
        tail -n 5 "$work/first.log"
        failed+=("$distribution")
        continue
    fi
    echo "$distribution: make demo stopped in $(seconds_since "$start") s: $line"

    # 2. A venv without pip, as python3 -m venv leaves one where the system lacks ensurepip.
    in_root python3 -m venv --without-pip /root/simple_robot_control/.venv

    # 3. The set-up step (the container image's), which installs what the line named.
    start=$(date +%s)
    in_root /root/simple_robot_control/scripts/setup_system.sh > "$work/setup.log" 2>&1 || {
        echo "$distribution: FAIL: setup_system.sh"; tail -n 5 "$work/setup.log"
        failed+=("$distribution"); continue; }
    echo "$distribution: scripts/setup_system.sh in $(seconds_since "$start") s"

    # 4. The demo, to FINISHED.
    start=$(date +%s)
    if in_root bash -c 'cd /root/simple_robot_control && make demo' > "$work/demo.log" 2>&1 \
            && grep -q 'FINISHED' "$work/demo.log"; then
        echo "$distribution: make demo printed FINISHED in $(seconds_since "$start") s" \
            "(from a venv without pip: made again)"
    else
        echo "$distribution: FAIL: make demo (last lines below)"
        tail -n 15 "$work/demo.log"
        failed+=("$distribution")
    fi
    rm -rf --one-file-system "$root"
done
if [ ${#failed[@]} -gt 0 ]; then
    echo "fresh-linux: FAILED on ${failed[*]}"
    exit 1
fi
echo "fresh-linux: passed on ${distributions[*]}"
