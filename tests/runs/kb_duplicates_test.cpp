// A merge's refusal of duplicate inputs (lib/runs/kb_duplicates.cpp), whose
// policies would count twice: the same file, two KBs of equal content digest,
// or two KBs that observed the same source run; distinct KBs are accepted.
#include "runs/kb_duplicates.hpp"

#include <catch2/catch.hpp>

#include "runs/kb_files.hpp"
#include "support/kb_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// refuse_duplicate_kbs on the KB files `inputs`, loaded as a merge loads them
void check(const std::vector<std::filesystem::path>& inputs) {
    std::vector<db::StoredKb> loaded;
    for (const auto& path : inputs) loaded.push_back(runs::load_kb_file(path, ""));
    runs::refuse_duplicate_kbs(inputs, loaded);
}

}  // namespace

TEST_CASE("two KBs of equal digest are refused as duplicates, distinct ones accepted", "[runs][kb][merge]") {
    test::TempDir dir;
    // policies {x, y, reward, generation}: a and its copy hold the same KB in two files
    const auto a = kbtest::point_kb("run-a", {{0, 0, 1, 0}, {3, 3, 0.5, 1}});
    kbtest::write_kb(dir / "a.db", "a", a);
    kbtest::write_kb(dir / "copy.db", "copy", a);
    kbtest::write_kb(dir / "b.db", "b", kbtest::point_kb("run-b", {{5, 5, 1, 0}}));
    // another content, but the same source run: run-a, generations 0 to 1, 2 policies
    kbtest::write_kb(dir / "again.db", "again",
                     kbtest::point_kb("run-a", {{1, 1, 0.25, 0}, {2, 2, 0.75, 1}}));

    CHECK_NOTHROW(check({dir / "a.db", dir / "b.db"}));
    CHECK_NOTHROW(check({dir / "b.db", dir / "again.db"}));

    const std::string a_db = (dir / "a.db").string(), copy_db = (dir / "copy.db").string();
    CHECK_THROWS_AS(check({dir / "a.db", dir / "copy.db"}), runs::DuplicateKbs);
    CHECK_THROWS_WITH(check({dir / "a.db", dir / "b.db", dir / "copy.db"}),
                      "cannot merge " + copy_db + " with " + a_db +
                          ": they hold the same knowledge base, so its policies would count twice");
    CHECK_THROWS_WITH(check({dir / "a.db", dir / "a.db"}), Contains("they are the same file"));
    CHECK_THROWS_WITH(check({dir / "a.db", dir / "again.db"}), Contains("both observed run \"run-a\""));
}
