# Comments describe the present: no changelog ("issue 23", "the sixth round", "as it always was") in the code, the
# scripts or the INI files. What was tried, and when, belongs in docs/experiments.md and the closing notes.
set -euo pipefail
cd "$(dirname "$0")/.."
pattern='issue [0-9]+|\b(first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth) (round|session)\b|as it always was'
if hits=$(grep -rnEi "$pattern" libs apps rawlog_tools tests fuzz scripts share config.ini --exclude=changelog_comments.sh); then
  echo "$hits"
  echo "error: changelog in comments (above); move the history to docs/experiments.md" >&2
  exit 1
fi
echo "OK: no changelog in libs apps rawlog_tools tests fuzz scripts share config.ini"
