# The Debian 13 root shared by the test lanes on other dolfinx versions (sourced by scripts/debian13.sh and
# scripts/wheel011.sh). The root folder ($DEB13, default ~/.cache/fenics_contact/debian13: one per machine, so a
# fresh clone reuses it) is made once with debootstrap and reused.
# The sourcing script sets LANE (its name in messages) and OPTIONAL (1: skip, saying why, where the lane cannot run).
DEB13=${DEB13:-${XDG_CACHE_HOME:-$HOME/.cache}/fenics_contact/debian13}
OPTIONAL=${OPTIONAL:-0}

skip() {
  if [ "$OPTIONAL" = 1 ]; then echo "$LANE lane: SKIPPED: $1"; exit 0; fi
  echo "$LANE lane: cannot run: $1" >&2; exit 1
}

# The root with its package lists, made by debootstrap if missing.
lane_root() {
  [ "$(id -u)" -eq 0 ] || skip "needs root (chroot)"
  if ! command -v debootstrap >/dev/null; then
    command -v apt-get >/dev/null || skip "no debootstrap and no apt-get to install it"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q debootstrap >/dev/null \
      || skip "apt-get install debootstrap failed"
  fi
  if [ ! -x "$DEB13/usr/bin/apt-get" ]; then
    echo "$LANE lane: debootstrap --variant=minbase trixie $DEB13"
    rm -rf "$DEB13" && mkdir -p "$(dirname "$DEB13")"
    debootstrap --variant=minbase trixie "$DEB13" >/dev/null || skip "debootstrap failed"
    # A throwaway test root: no fsync per package, no documentation (fresh lane measured: 4 min here).
    echo force-unsafe-io > "$DEB13/etc/dpkg/dpkg.cfg.d/unsafe-io"
    printf 'path-exclude /usr/share/doc/*\npath-exclude /usr/share/man/*\npath-exclude /usr/share/locale/*\n' \
      > "$DEB13/etc/dpkg/dpkg.cfg.d/nodoc"
  fi
  # The host's name server (the root's may be older than the host's network).
  cp /etc/resolv.conf "$DEB13/etc/resolv.conf" 2>/dev/null || true
}

# apt-get install the given packages in the root, those not yet installed.
lane_apt() {
  local missing=()
  for p in "$@"; do chroot "$DEB13" dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "$LANE lane: installing ${missing[*]} in $DEB13"
  chroot "$DEB13" /bin/sh -c "apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q \
    --no-install-recommends ${missing[*]} >/dev/null"
}

# Copy the project into the root's folder $1 (relative to the root), afresh.
lane_copy() {
  rm -rf "${DEB13:?}/$1" && mkdir -p "$DEB13/$1"
  cp -a pyproject.toml README.md LICENSE Makefile fenics_contact tests scripts demos docs tutorials "$DEB13/$1/"
  find "$DEB13/$1" -name __pycache__ -prune -exec rm -rf {} +
}

# Run the shell command $1 in the root, in its folder /$2, with a clean environment plus the NAME=VALUE words that
# follow, and /proc and /sys mounted (MPICH needs both). The mounts are made in a private mount namespace: they exist
# only for this command's processes and go with the last of them, whether it passed, failed or was killed, and two
# lanes at once do not see each other's.
lane_mounted() {
  local cmd=$1 dir=$2
  shift 2
  unshare --mount --propagation private /bin/sh -c \
    'root=$1; shift; mount -t proc proc "$root/proc" && mount --bind /sys "$root/sys" && exec chroot "$root" "$@"' \
    sh "$DEB13" /usr/bin/env -i HOME=/root PATH=/usr/local/bin:/usr/bin:/bin "$@" /bin/sh -c "cd /$dir && $cmd"
}
