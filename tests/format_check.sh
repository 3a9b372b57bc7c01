#!/usr/bin/env bash
# The C++ sources follow .clang-format: the files that do not are listed, with what clang-format would change first.
set -euo pipefail
CLANG_FORMAT="${1:?usage: format_check.sh <clang-format>}"
cd "$(dirname "$0")/.."
mapfile -t files < <(find libs apps rawlog_tools tests fuzz \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' -o -name '*.cc' \) | sort)
if ! report=$("$CLANG_FORMAT" --dry-run -Werror "${files[@]}" 2>&1); then
  echo "$report" | head -20
  echo "$report" | grep -oE '^[^:]+:[0-9]+:[0-9]+: error' | cut -d: -f1 | sort -u
  echo "error: files above differ from .clang-format; run: $CLANG_FORMAT -i <files>" >&2
  exit 1
fi
echo "OK: ${#files[@]} files follow .clang-format"
