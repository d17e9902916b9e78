#!/usr/bin/env bash
# `pip install --no-build-isolation .` of a copy of the source tree into a new virtual
# environment made with --system-site-packages (Debian's numpy and setuptools), offline;
# then `import stepstone` from outside the tree must load the installed module.
# The module is built in BUILD_DIR (this build tree: only linked again if needed).
# Usage: pip_install.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src="$1"
build="$2"
work="$3"
rm -rf "$work"
mkdir -p "$work"
# a copy of the tracked files, as a fresh clone holds them
mkdir -p "$work/clone"
git -C "$src" ls-files -z | (cd "$src" && xargs -0 cp --parents -t "$work/clone")
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
STEPSTONE_BUILD_DIR="$build" "$work/venv/bin/pip" install --quiet --no-build-isolation --no-index \
    --no-cache-dir "$work/clone" > "$work/pip.log" 2>&1 || { cat "$work/pip.log"; exit 1; }
cd "$work"  # outside the clone: the installed module, not a build tree
where="$("$work/venv/bin/python" -c 'import stepstone; print(stepstone.__file__)')"
case "$where" in
    "$work/venv/"*) ;;
    *) echo "pip_install: stepstone loaded from $where, not from the virtual environment"; exit 1 ;;
esac
"$work/venv/bin/python" -c '
import pathlib, stepstone
kb = stepstone.KnowledgeBase(width=20, channels=15, delta=1.83)
assert len(kb) == 0 and stepstone.Task().arena == stepstone.paper_arena()
print("pip_install: stepstone", pathlib.Path(stepstone.__file__).name, "imports from the venv")
'
