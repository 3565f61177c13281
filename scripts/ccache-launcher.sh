# Sourced by the build scripts: sets `launcher` to the CMake arguments that
# compile through ccache where it is installed (it is never required).
# Hits must survive a fresh clone at another path (CI builds one): ccache takes
# paths relative to the checkout, and does not hash the working directory,
# which it otherwise does for every -g build (the sanitizer and fuzz builds).
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
