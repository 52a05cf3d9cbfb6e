# Sourced by the Blender tests (tests/blender/*.sh): finds Blender and makes the corpus.
#
# require_blender: sets $blender, or exits 77 (ctest: skipped) when Blender is missing, except
# under CI (env CI set), where that is a failure: scripts/setup.sh installs Debian's blender.
# LIGHTBAKE_BLENDER names another executable.
#
# make_scene SCENE DIR [make_scene.py options...]: runs tests/blender/make_scene.py in
# Blender (niced: it takes every core) unless DIR holds its output for the same script, Blender
# version and options already (a stamp file keyed by their SHA-256), so reruns are free. Its
# log is DIR/SCENE_OPTIONS.log. Needs $source (the source tree).

require_blender() {
  blender=${LIGHTBAKE_BLENDER:-blender}
  if ! command -v "$blender" > /dev/null; then
    if [[ -n ${CI:-} ]]; then
      echo "error: CI needs Blender ($blender): scripts/setup.sh installs Debian's blender"
      exit 1
    fi
    echo "skipped: needs Blender ($blender; scripts/setup.sh installs Debian's blender)"
    exit 77
  fi
}

make_scene() {
  local scene=$1 dir=$2
  shift 2
  local name="${scene}${*:+_}$(printf '%s' "$*" | tr -c 'A-Za-z0-9_.-' '_')"
  local key
  key=$( { cat "$source/tests/blender/make_scene.py"; "$blender" --version 2> /dev/null | head -1;
           echo "$scene $*"; } | sha256sum | cut -d' ' -f1)
  mkdir -p "$dir"
  if [[ -f $dir/$name.stamp && $(cat "$dir/$name.stamp") == "$key" ]]; then
    return 0
  fi
  rm -f "$dir/$name.stamp"
  local start=$SECONDS
  # --python-exit-code: a Python exception fails the run (Blender exits 0 otherwise).
  if ! nice "$blender" -b --factory-startup --python-exit-code 1 \
       --python "$source/tests/blender/make_scene.py" -- "$scene" "$dir" "$@" \
       > "$dir/$name.log" 2>&1; then
    echo "error: make_scene.py $scene $* failed; the end of $dir/$name.log:"
    tail -n 20 "$dir/$name.log"
    exit 1
  fi
  echo "made $scene $* in $dir ($((SECONDS - start)) s)"
  echo "$key" > "$dir/$name.stamp"
}
