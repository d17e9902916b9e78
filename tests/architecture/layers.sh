#!/usr/bin/env bash
# The structure docs/architecture.md describes, checked on the source tree:
#   1. the read side (lib/runs) and what reads runs (lib/report, lib/service)
#      include nothing of the engine (lib/exp), and link no engine target;
#   1b. the SQL that reads run and campaign files lives in lib/runs: lib/service includes
#      nothing of lib/report, and neither names db::sql, Statement or sqlite3, nor hands a
#      literal to a connection's prepare, exec or query_int;
#   2. no library message names a CLI flag (--name in a string literal);
#      the libraries name options as `name` (core/text.hpp: option_name);
#   3. no file of the library, the app, bench/ or reference/ is over 600 lines;
#   4. no test name holds ';' or '[' (ctest would split it, Catch read a tag);
#   5. the service uses only the public API of the libraries it serves with: it names no
#      private or protected member of cpp-httplib, subclasses none of its classes and includes
#      no header of a library's internals (docs/service.md, "How the bounds are kept");
#   6. the library (lib/) includes and links nothing of bench/ or reference/, which sit beside it.
# Usage: layers.sh SOURCE_DIR. Prints every violation; exit 1 if any.
set -euo pipefail
src="$1"
cd "$src"
failures=0
fail() { echo "layers: $*"; failures=$((failures + 1)); }

for module in runs report service; do
    while IFS= read -r hit; do fail "lib/$module uses the engine: $hit"; done \
        < <(grep -rn '#include "exp/' "lib/$module" || true)
    if grep -q 'stepstone::exp' "lib/$module/CMakeLists.txt"; then
        fail "lib/$module/CMakeLists.txt links stepstone::exp"
    fi
done

while IFS= read -r hit; do fail "lib/service uses the report module: $hit"; done \
    < <(grep -rn '#include "report/' lib/service || true)
while IFS= read -r hit; do fail "SQL outside lib/runs (read runs and campaigns through it): $hit"; done \
    < <(grep -rnE 'db::sql\b|\bStatement\b|sqlite3|\b(prepare|prepare_all|exec|query_int)\(\s*"' lib/report lib/service \
            | grep -vE '^[^:]+:[0-9]+:\s*//' || true)

# string literals holding --word, outside comments (bench/, beside the library, starts mpirun
# and stepstone with their flags)
while IFS= read -r hit; do fail "a library message names a flag: $hit"; done \
    < <(grep -rnE '"[^"]*--[a-z][a-z-]*' lib --include='*.cpp' --include='*.hpp' \
            | grep -vE '^[^:]+:[0-9]+:\s*//' || true)

# the library stands without the benchmarks and the reference implementations
while IFS= read -r hit; do fail "the library uses bench/ or reference/: $hit"; done \
    < <(grep -rnE '#include\s*"(bench|reference)/|stepstone(::|_)(bench|reference)' lib || true)

# a run's sines, cosines and bearings come through sim/cos_sin.hpp, which picks glibc's or the
# portable ones by the run's "math"; the scripted controller is not a run
while IFS= read -r hit; do fail "a math-library call outside sim/cos_sin.hpp: $hit"; done \
    < <(grep -rnE 'std::(sin|cos|atan2|tan|asin|acos|atan)\(' lib/sim --include='*.cpp' --include='*.hpp' \
            | grep -vE '^lib/sim/(cos_sin\.hpp|controllers\.cpp):' || true)

# cpp-httplib's private and protected members of Server (0.11.4), a subclass of its classes, and the
# detail/impl headers of a library (Boost's `detail` or `impl` folders): none in the service, comments aside
httplib_internals='process_and_close_socket|process_request|svr_sock_|is_running_|keep_alive_max_count_|'
httplib_internals+='keep_alive_timeout_sec_|read_timeout_(u?sec)_|write_timeout_(u?sec)_|idle_interval_(u?sec)_|'
httplib_internals+='payload_max_length_|listen_internal|bind_internal|create_server_socket|read_content|'
httplib_internals+='dispatch_request|routing\(|write_response|httplib::detail::'
while IFS= read -r hit; do fail "the service reaches into a library's internals: $hit"; done \
    < <(grep -rnE "($httplib_internals)|(:|public|protected|private)\s+(virtual\s+)?httplib::|#include\s*[<\"][^>\"]*/(detail|impl)/" \
            lib/service apps/stepstone/cmd_serve.cpp --include='*.cpp' --include='*.hpp' \
            | grep -vE '^[^:]+:[0-9]+:\s*//' || true)

# ctest splits a test name at ';', Catch reads '[' as a tag and a leading '-' as an option: such a
# case would run nothing. perl reads each file whole, as clang-format may wrap the name.
while IFS= read -r hit; do fail "a test name ctest or Catch would misread: $hit"; done \
    < <(find tests -name '*.cpp' -print0 | xargs -0 perl -0777 -ne \
            'while (/TEST_CASE\(\s*"([^"]*)"/g) { my $n = $1; print "$ARGV: $n\n" if $n =~ /^-|[][;]/; }' || true)

while read -r lines file; do
    [ "$file" = total ] && continue
    [ "$lines" -gt 600 ] && fail "$file has $lines lines (most files stay under 600)"
done < <(find lib apps bench reference -name '*.cpp' -o -name '*.hpp' | xargs wc -l)

if [ "$failures" -gt 0 ]; then
    echo "layers: $failures violation(s)"
    exit 1
fi
echo "layers: runs, report and service stay off the engine; SQL reads in runs only; the service on public library APIs only; no flag in a library message; the library off bench/ and reference/; no file over 600 lines"
