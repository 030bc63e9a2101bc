#!/usr/bin/env bash
# Installs the Debian packages designer needs, when they are missing:
#   install-system-packages.sh demo   what `make demo` runs on: the C compiler that builds
#                                     designer's compiled kernels and the X client and GL
#                                     libraries Blender's bpy loads (headless)
#   install-system-packages.sh all    (the default) those and what only the tests and the
#                                     GUI use: Xvfb, the xcb libraries Qt's platform plugin
#                                     loads, CloudCompare and COLMAP's command line (the
#                                     tests check exports and distances against them)
# As root it uses apt-get; otherwise it names the packages to install and stops.
set -euo pipefail
what="${1:-all}"
demo_packages=(
  gcc libc6-dev
  libgl1 libegl1 libxrender1 libxi6 libxkbcommon0 libxxf86vm1 libsm6 libice6
)
test_packages=(
  xvfb xauth
  libxkbcommon-x11-0
  libxcb-cursor0 libxcb-icccm4 libxcb-keysyms1 libxcb-shape0 libxcb-xinerama0
  libxcb-randr0 libxcb-render-util0 libxcb-image0
  cloudcompare colmap
)
case "$what" in
  demo) packages=("${demo_packages[@]}") ;;
  all) packages=("${demo_packages[@]}" "${test_packages[@]}") ;;
  *) echo "error: unknown package set '$what'; give demo or all" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null; then
  echo "error: missing system packages (${missing[*]}) and no apt-get; install them with your package manager" >&2
  exit 1
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "error: missing system packages; run: sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "installing system packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
