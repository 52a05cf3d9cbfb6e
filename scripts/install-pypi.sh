#!/usr/bin/env bash
# Installs the PyPI packages the tests need into BUILD_DIR/pypi, by name, when missing:
# pyoidn 2.5.1.0 ships Intel Open Image Denoise's library (export --denoise; Debian has no
# package), which lightbake finds at BUILD_DIR/pypi/pyoidn/oidn/lib/ (bake/lightmap/oidn.h).
# --no-deps: only its library is used, not its Python bindings (numpy, cffi).
set -euo pipefail
build=${1:?usage: scripts/install-pypi.sh BUILD_DIR}
if [[ ! -f $build/pypi/pyoidn/oidn/lib/libOpenImageDenoise.so.2 ]]; then
  /usr/bin/python3 -m pip install --quiet --disable-pip-version-check --root-user-action=ignore --no-deps \
    --target "$build/pypi" pyoidn==2.5.1.0
fi
