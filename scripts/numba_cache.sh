# Sourced by scripts/paper and scripts/test (from the repository root): where numba keeps the
# compiled kernels. numba checks only a kernel's own file for changes, not the files of the
# helpers compiled into it, so after an update a cache shared across versions could serve a
# kernel with an old helper inside. The folder is therefore keyed by the package's sources,
# and the folders of other versions are removed. A NUMBA_CACHE_DIR already set is kept.
if [ -z "${NUMBA_CACHE_DIR:-}" ]; then
  key=$(find src/brakeca -name "*.py" | sort | xargs cat | sha256sum | cut -c1-16)
  for old in .numba_cache/*/; do
    if [ -d "$old" ] && [ "$old" != ".numba_cache/$key/" ]; then rm -rf "$old"; fi
  done
  export NUMBA_CACHE_DIR=$PWD/.numba_cache/$key
fi
