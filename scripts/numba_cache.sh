# Sourced by scripts/paper and scripts/test (from the repository root): where numba keeps the
# compiled kernels. numba checks only a kernel's own file for changes, not the files of the
# helpers compiled into it, so after an update a cache shared across versions could serve a
# kernel with an old helper inside. The folder is therefore keyed by the package's sources
# that compiled code comes from (brakeca._cachedir.source_key, which needs only the standard
# library), and the folders of other versions are removed. A NUMBA_CACHE_DIR already set is kept.
if [ -z "${NUMBA_CACHE_DIR:-}" ]; then
  key=$(.venv/bin/python -c "import sys; sys.path.insert(0, 'src'); from brakeca._cachedir import source_key; print(source_key())")
  for old in .numba_cache/*/; do
    if [ -d "$old" ] && [ "$old" != ".numba_cache/$key/" ]; then rm -rf "$old"; fi
  done
  export NUMBA_CACHE_DIR=$PWD/.numba_cache/$key
fi
