#!/usr/bin/env bash
# Install lockstep's build and test dependencies from Debian 12 packages.
# Idempotent: when everything is present it only runs dpkg-query (a second or so).
#   --peers  also the production peers that are large to install: VTK
#            (libvtk9-dev, about 150 packages; the marching_cubes family's vtk row).
#            Without them those rows are simply not built.
set -euo pipefail

peers=0
for a in "$@"; do
  case "$a" in
    --peers) peers=1 ;;
    *) echo "setup: unknown option $a (usage: setup.sh [--peers])" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build pkg-config
  libembree-dev libcgal-dev libgmp-dev libmpfr-dev
  libopenimageio-dev openimageio-tools
  libopenexr-dev libpng-dev  # .exr and .png without OpenImageIO (io/image_exr.cpp, io/image_png.cpp)
  libbenchmark-dev librapidcheck-dev libgtest-dev
  libtbb-dev libhwy-dev gnuplot-nox
  libosmesa6-dev libgl-dev  # the zbuffer family's llvmpipe row (Mesa OSMesa; GL/gl.h, GL/glext.h)
  python3-skimage  # tests/topology_skimage.py: marching cubes against Lewiner's MC33 (scikit-image), run with /usr/bin/python3
  libteem-dev zlib1g-dev  # volumes: Teem's nrrd library reads NRRD (io/volume_io.cpp); zlib writes the tests' gzip files
  libvolpack1-dev  # the volume family's volpack row (VolPack shear-warp; optional, as OSMesa)
  povray  # the ray_trace family's povray row (POV-Ray 3.7, run as a process; optional, as VolPack)
  chromium nodejs  # tests/browser: the report page in a real browser (report.browser), driven by puppeteer-core
  libxml2-utils python3-jsonschema  # tests/schemas: xmllint validates --junit, jsonschema validates --json
)
# npm comes with NodeSource's nodejs; Debian's nodejs needs Debian's npm.
command -v npm >/dev/null || packages+=(npm)

if ((peers)); then
  packages+=(libvtk9-dev)  # vtkFlyingEdges3D (optimized/marching_cubes_vtk.cpp)
  packages+=(python3-vtk9)  # the same filter as VTK's Python users call it (bench/scripts/oneshot_pages.py)
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
else
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# puppeteer-core (pinned in tests/browser/package-lock.json) drives Debian's
# chromium for report.browser; installed into the git-ignored
# tests/browser/node_modules, skipped when that version is there already.
browser="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/browser"
want=$(sed -n 's/.*"puppeteer-core": "\(.*\)".*/\1/p' "$browser/package.json")
have=$(sed -n 's/^  "version": "\(.*\)",$/\1/p' "$browser/node_modules/puppeteer-core/package.json" 2>/dev/null || true)
if [[ "$have" != "$want" ]]; then
  echo "setup: npm ci puppeteer-core@$want into tests/browser/node_modules"
  (cd "$browser" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi
echo "setup: done"
