#!/bin/bash
# wine.prefix: creates the shared Wine prefix of the build tree once (the
# ctest fixture the other Wine tests require), so its ~25 s are counted here.
source "$(dirname "$0")/common.sh"
find_tools
mkdir -p "$RT64K_WINE_DIR"
prepare_prefix
"$WINE" --version
echo "PASS: prefix $WINEPREFIX"
