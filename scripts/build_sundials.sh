#!/usr/bin/env bash
# Builds SUNDIALS 6.4.1 with optimisation from Debian's own source package and installs it into
# a per-user cache, where CMake prefers it (cmake/MbstreamSundials.cmake) over Debian's
# libsundials-dev, whose binaries are built without optimisation (issue 15).
#
#   scripts/build_sundials.sh                 build unless the cache already holds this build
#   scripts/build_sundials.sh --print-prefix  print the install prefix and exit (CMake asks this)
#
# What is built: CVODE, ARKODE, IDA, the generic modules they carry (serial vector, dense and
# sparse matrices, dense solver, Newton and fixed-point nonlinear solvers) and the KLU solver, as
# static libraries with -O3 -DNDEBUG -fPIC; no examples, no CVODES/IDAS/KINSOL, no MPI/OpenMP.
# Static: nothing to find at run time, no clash with Debian's libsundials_*.so.6 of the same
# soname, and the sanitizer builds link it like any other object code.
#
# The cache is $MBSTREAM_CACHE_DIR (default ${XDG_CACHE_HOME:-$HOME/.cache}/mbstream), one folder
# per version and flags: sundials-6.4.1-<hash of the configure options>. A second checkout or a
# CI run on the same machine reuses it; a complete install carries a .complete stamp, so a run
# that was interrupted is redone, and the script is quick and quiet when the cache is complete.
#
# The source comes from `apt-get source` with a private apt configuration (a temporary sources
# list holding a deb-src line derived from the machine's own deb entry, a private lists and cache
# folder), so the machine's apt configuration and package lists are never changed. It exits
# non-zero when the source can't be fetched or built; scripts/setup.sh then goes on with
# Debian's binary package, loudly.
set -euo pipefail

SUNDIALS_VERSION=6.4.1
JOBS=${MBSTREAM_SUNDIALS_JOBS:-2}
CACHE_ROOT=${MBSTREAM_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/mbstream}

multiarch=$(gcc -print-multiarch 2>/dev/null || true)
klu_libdir=/usr/lib${multiarch:+/$multiarch}

# Every option that changes the built code is in this list, and the list names the cache folder.
CONFIGURE_OPTIONS=(
  -DCMAKE_BUILD_TYPE=Release
  "-DCMAKE_C_FLAGS_RELEASE=-O3 -DNDEBUG"
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON
  -DBUILD_STATIC_LIBS=ON -DBUILD_SHARED_LIBS=OFF
  -DBUILD_CVODE=ON -DBUILD_ARKODE=ON -DBUILD_IDA=ON
  -DBUILD_CVODES=OFF -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF
  -DBUILD_NVECTOR_MANYVECTOR=OFF -DBUILD_FORTRAN_MODULE_INTERFACE=OFF
  -DENABLE_MPI=OFF -DENABLE_OPENMP=OFF -DENABLE_PTHREAD=OFF -DENABLE_LAPACK=OFF
  -DENABLE_KLU=ON -DKLU_INCLUDE_DIR=/usr/include/suitesparse -DKLU_LIBRARY_DIR="$klu_libdir"
  -DSUNDIALS_INDEX_SIZE=64
  -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF
  -DBUILD_TESTING=OFF
)
key=$(printf '%s\n' "$SUNDIALS_VERSION" "${CONFIGURE_OPTIONS[@]}" | sha256sum | cut -c1-10)
PREFIX="$CACHE_ROOT/sundials-$SUNDIALS_VERSION-$key"

if [ "${1:-}" = "--print-prefix" ]; then
  echo "$PREFIX"
  exit 0
fi

if [ -f "$PREFIX/.complete" ]; then
  exit 0
fi

say() { echo "build_sundials: $*" >&2; }

mkdir -p "$CACHE_ROOT"
# One build at a time per cache (two setups started together wait for each other).
exec 9>"$CACHE_ROOT/.sundials-$SUNDIALS_VERSION-$key.lock"
flock 9
if [ -f "$PREFIX/.complete" ]; then
  exit 0
fi

for tool in apt-get dpkg-source cmake make gcc; do
  if ! command -v "$tool" >/dev/null; then
    say "needs $tool (scripts/setup.sh installs it)"
    exit 1
  fi
done
if [ ! -f /usr/include/suitesparse/klu.h ]; then
  say "needs libsuitesparse-dev (KLU)"
  exit 1
fi

work=$(mktemp -d "$CACHE_ROOT/.sundials-work.XXXXXX")
trap 'rm -rf "$work"' EXIT
# apt's download sandbox user must be able to write here.
chmod 755 "$work"

# --- a private apt configuration with one deb-src line -------------------------------------
# The archive the machine uses: the first 'deb' entry of its own sources (deb822 .sources files
# or one-line .list files) whose suite is this release's codename. Read at run time: no archive
# host is written in this repository.
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
if [ -z "$codename" ]; then
  say "no VERSION_CODENAME in /etc/os-release"
  exit 1
fi
srcline=""
shopt -s nullglob
for f in /etc/apt/sources.list.d/*.sources; do
  # deb822: blank-line separated stanzas of 'Field: value'.
  srcline=$(awk -v codename="$codename" '
    function flush() {
      if (types ~ /(^| )deb( |$)/ && (" " suites " ") ~ (" " codename " ") && uri != "" && line == "") {
        line = "deb-src" (signed != "" ? " [signed-by=" signed "]" : "") " " uri " " codename " " comps
      }
      types = ""; uri = ""; suites = ""; comps = ""; signed = ""
    }
    /^[ \t]*#/ { next }
    /^[ \t]*$/ { flush(); next }
    /^Types:/ { sub(/^Types:[ \t]*/, ""); types = $0 }
    /^URIs:/ { sub(/^URIs:[ \t]*/, ""); split($0, u, /[ \t]+/); uri = u[1] }
    /^Suites:/ { sub(/^Suites:[ \t]*/, ""); suites = $0 }
    /^Components:/ { sub(/^Components:[ \t]*/, ""); comps = $0 }
    /^Signed-By:/ { sub(/^Signed-By:[ \t]*/, ""); signed = $0 }
    END { flush(); print line }' "$f")
  [ -n "$srcline" ] && break
done
if [ -z "$srcline" ]; then
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    # One-line form: deb [options] uri suite components...
    srcline=$(awk -v codename="$codename" '
      $1 == "deb" {
        opts = ""; i = 2
        if ($2 ~ /^\[/) { while ($i !~ /\]$/) { opts = opts $i " "; i++ } opts = opts $i " "; i++ }
        if ($(i + 1) == codename) {
          line = "deb-src " opts $i " " codename
          for (j = i + 2; j <= NF && $j !~ /^#/; j++) line = line " " $j
          print line; exit
        }
      }' "$f")
    [ -n "$srcline" ] && break
  done
fi
shopt -u nullglob
if [ -z "$srcline" ]; then
  say "found no 'deb' entry for $codename in the machine's apt sources"
  exit 1
fi

mkdir -p "$work/apt/lists/partial" "$work/apt/cache/archives/partial" "$work/src"
echo "$srcline" >"$work/apt/sources.list"
APT_PRIVATE=(
  -o Dir::Etc::sourcelist="$work/apt/sources.list"
  -o Dir::Etc::sourceparts=-
  -o Dir::State::Lists="$work/apt/lists"
  -o Dir::Cache="$work/apt/cache"
  -o Dir::Cache::pkgcache=
  -o Dir::Cache::srcpkgcache=
)
start=$(date +%s)
say "fetching Debian's source package of SUNDIALS $SUNDIALS_VERSION (private apt configuration)"
if ! apt-get "${APT_PRIVATE[@]}" -qq update >"$work/apt.log" 2>&1; then
  cat "$work/apt.log" >&2
  say "apt-get update of the private deb-src list failed"
  exit 1
fi
if ! (cd "$work/src" && apt-get "${APT_PRIVATE[@]}" -qq source --only-source sundials) >>"$work/apt.log" 2>&1; then
  cat "$work/apt.log" >&2
  say "apt-get source sundials failed"
  exit 1
fi
srcdir=$(find "$work/src" -mindepth 1 -maxdepth 1 -type d -name "sundials-$SUNDIALS_VERSION*" | head -n 1)
if [ -z "$srcdir" ]; then
  say "the archive's source package is not SUNDIALS $SUNDIALS_VERSION: $(ls "$work/src" | tr '\n' ' ')"
  exit 1
fi
say "building $(basename "$srcdir") (CVODE, ARKODE, IDA, KLU; -O3 -DNDEBUG, static) into $PREFIX"

# --- configure, build, install; the .complete stamp comes last ------------------------------
rm -rf "$PREFIX"
if ! cmake -S "$srcdir" -B "$work/build" "${CONFIGURE_OPTIONS[@]}" \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_INSTALL_LIBDIR=lib >"$work/build.log" 2>&1 ||
  ! cmake --build "$work/build" --parallel "$JOBS" >>"$work/build.log" 2>&1 ||
  ! cmake --install "$work/build" >>"$work/build.log" 2>&1; then
  tail -n 40 "$work/build.log" >&2
  rm -rf "$PREFIX"
  say "building SUNDIALS failed"
  exit 1
fi
printf 'SUNDIALS %s from %s\n' "$SUNDIALS_VERSION" "$(basename "$srcdir")" >"$PREFIX/BUILD-INFO"
printf '%s\n' "${CONFIGURE_OPTIONS[@]}" >>"$PREFIX/BUILD-INFO"
touch "$PREFIX/.complete"
say "done in $(($(date +%s) - start)) s: $PREFIX"
