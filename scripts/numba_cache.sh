# Sourced by scripts/paper and scripts/test: where numba keeps the compiled kernels. numba
# checks only a kernel's own file for changes, not the files of the helpers compiled into it,
# so after an update a cache shared across versions could serve a kernel with an old helper
# inside. The folder is therefore keyed by the package's sources that compiled code comes from
# (brakeca._cachedir.source_key, which needs only the standard library), and the folders of
# other versions are removed. A NUMBA_CACHE_DIR already set is kept. The folder is the
# repository's .numba_cache/<key>, from wherever bash sources this file (another sh: from the
# repository's root).
if [ -z "${NUMBA_CACHE_DIR:-}" ]; then
  # bash knows the file sourced (BASH_SOURCE); another sh, from the repository root
  if [ -n "${BASH_SOURCE:-}" ]; then
    _brakeca_root=$(cd "$(dirname "$BASH_SOURCE")/.." && pwd)
  else
    _brakeca_root=$PWD
  fi
  _brakeca_key=$("$_brakeca_root/.venv/bin/python" -c "import sys; sys.path.insert(0, sys.argv[1]); from brakeca._cachedir import source_key; print(source_key())" "$_brakeca_root/src")
  if [ -z "$_brakeca_key" ]; then
    # without a key the folder would be shared across versions (and every other removed)
    echo "numba_cache.sh: no cache key from $_brakeca_root/.venv (run scripts/bootstrap first); NUMBA_CACHE_DIR not set" >&2
  else
    for old in "$_brakeca_root"/.numba_cache/*/; do
      if [ -d "$old" ] && [ "$old" != "$_brakeca_root/.numba_cache/$_brakeca_key/" ]; then rm -rf "$old"; fi
    done
    export NUMBA_CACHE_DIR=$_brakeca_root/.numba_cache/$_brakeca_key
  fi
  unset _brakeca_root _brakeca_key
fi
