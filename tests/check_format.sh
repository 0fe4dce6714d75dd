#!/bin/sh
# Every C source and header is formatted as the committed .clang-format says (clang-format 14,
# Debian 12's). Fix with: clang-format -i FILE (tables that read better by hand sit between
# "clang-format off" and "clang-format on" comments).
#   check_format.sh SOURCE_DIR
set -eu
cd "$1"
command -v clang-format >/dev/null || { echo "clang-format is not installed (scripts/deps.sh installs it)"; exit 1; }
find app bench fuzz include src tests -name '*.[ch]' -print0 | xargs -0 clang-format --dry-run -Werror
echo "formatted: $(find app bench fuzz include src tests -name '*.[ch]' | wc -l) files"
