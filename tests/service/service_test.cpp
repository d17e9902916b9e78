// `stepstone serve` over loopback: every endpoint against the in-process
// library's answers, the documented 4xx for bad requests, concurrent clients,
// durable observations and the safety rules.

#include <httplib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "exp/kb_apply.hpp"
#include "kb/segments.hpp"
#include "report/runs.hpp"
#include "runs/replay.hpp"
#include "server_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;

namespace {

kb::KnowledgeBase load(const std::filesystem::path& file, const std::string& name = "") {
    auto connection = db::open_database(file, db::OpenMode::read_only);
    return db::load_kb(connection, name).kb;
}

json post(httplib::Client& client, const std::string& path, const json& body, int expected = 200) {
    const auto res = client.Post(path.c_str(), body.dump(), "application/json");
    REQUIRE(res);
    CAPTURE(path, res->body);
    REQUIRE(res->status == expected);
    return json::parse(res->body);
}

json get(httplib::Client& client, const std::string& path, int expected = 200) {
    const auto res = client.Get(path.c_str());
    REQUIRE(res);
    CAPTURE(path, res->body);
    REQUIRE(res->status == expected);
    return json::parse(res->body);
}

// segments near KB segments (some exact, some moved) and a few random ones
std::vector<std::vector<float>> probe_segments(const kb::KnowledgeBase& base, unsigned seed, std::size_t count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<std::vector<float>> out;
    for (std::size_t i = 0; i < count; ++i) {
        const auto source = base.segment(rng() % base.size());
        std::vector<float> s(source.begin(), source.end());
        if (i % 3 == 1) for (auto& v : s) v += 0.02f * (unit(rng) - 0.5f);
        if (i % 3 == 2) for (auto& v : s) v = unit(rng);
        out.push_back(std::move(s));
    }
    return out;
}

void check_matches(const json& answer, const kb::Lookup& expected) {
    REQUIRE(answer["matches"].size() == expected.segments.size());
    for (std::size_t i = 0; i < expected.segments.size(); ++i) {
        const auto& m = answer["matches"][i];
        const auto& e = expected.segments[i];
        CAPTURE(i);
        if (e.id) {
            CHECK(m["kb_segment_id"].get<std::size_t>() == *e.id);
        } else {
            CHECK(m["kb_segment_id"].is_null());
        }
        CHECK(m["distance"].get<double>() == e.distance);
        CHECK(m["average_reward"].get<double>() == e.average_reward);
    }
    CHECK(answer["r_max"].get<double>() == expected.r_max);
}

std::vector<float> flat(const std::vector<std::vector<float>>& segments) {
    std::vector<float> out;
    for (const auto& s : segments) out.insert(out.end(), s.begin(), s.end());
    return out;
}

json rows_of(const std::vector<float>& behaviour, std::size_t channels) {
    json rows = json::array();
    for (std::size_t r = 0; r < behaviour.size() / channels; ++r) {
        rows.push_back(std::vector<float>(behaviour.begin() + static_cast<long>(r * channels),
                                          behaviour.begin() + static_cast<long>((r + 1) * channels)));
    }
    return rows;
}

}  // namespace

TEST_CASE("every endpoint answers what the library computes in process", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto base = load(dir / "run.db", "run");
    ServerProcess server({(dir / "run.db").string()}, dir.path());
    httplib::Client client("127.0.0.1", server.port());

    CHECK(get(client, "/healthz")["status"] == "ok");
    const auto kbs = get(client, "/v1/kbs");
    REQUIRE(kbs.size() == 1);
    CHECK(kbs[0]["name"] == "run");
    CHECK(kbs[0]["segments"].get<std::size_t>() == base.size());
    CHECK(kbs[0]["max_average_reward"].get<double>() == base.max_average());
    const auto info = get(client, "/v1/kbs/run");
    std::uint64_t binned = 0;
    for (const auto& bin : info["histogram"]) binned += bin["segments"].get<std::uint64_t>();
    CHECK(binned == base.size());

    // lookup: segments in, each one's match and r_max out
    const auto probes = probe_segments(base, 3, 12);
    const auto values = flat(probes);
    const auto answer = post(client, "/v1/kbs/run/lookup", {{"segments", probes}});
    check_matches(answer, base.lookup(kb::as_segments(values, base.params().dim())));

    // shape: a whole behaviour matrix, as evolve segments and looks it up
    const auto behaviour = runs::replay_behaviour(dir / "run.db", "best");
    const auto shaped = post(client, "/v1/kbs/run/shape", {{"behaviour", rows_of(behaviour, 15)}});
    const auto expected = exp::shape_policy(dir / "run.db", dir / "run.db", "best", "run");
    CHECK(shaped["r_max"].get<double>() == expected.r_max);
    CHECK(shaped["matches"].size() == expected.segments.size());

    // the most salient segments with count >= 2, by a sort made here
    std::vector<std::size_t> ids;
    for (std::size_t id = 0; id < base.size(); ++id) {
        if (base.record(id).count >= 2) ids.push_back(id);
    }
    std::stable_sort(ids.begin(), ids.end(), [&](auto a, auto b) { return base.record(a).average() > base.record(b).average(); });
    const auto listed = get(client, "/v1/kbs/run/segments?order=reward&limit=5&min_count=2");
    CHECK(listed["matching"].get<std::size_t>() == ids.size());
    REQUIRE(listed["segments"].size() == std::min<std::size_t>(5, ids.size()));
    for (std::size_t k = 0; k < listed["segments"].size(); ++k) CHECK(listed["segments"][k]["id"] == ids[k]);

    // the run and its generations, as the file holds them
    const auto runs = get(client, "/v1/runs");
    REQUIRE(runs.size() == 1);
    CHECK(runs[0]["generations_done"] == 4);
    const auto generations = get(client, "/v1/runs/1/generations");
    REQUIRE(generations.size() == 5);
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto rows = connection.prepare("SELECT best_reward FROM generation ORDER BY generation");
    double top = -1;
    for (std::size_t g = 0; rows.step(); ++g) {
        CHECK(generations[g]["best_reward"].get<double>() == rows.column_double(0));
        top = std::max(top, rows.column_double(0));
    }
    CHECK(runs[0]["best_reward"].get<double>() == top);  // the run's best over its generations
    get(client, "/v1/campaign", 404);
    CHECK(server.stop() == 0);
}

TEST_CASE("bad requests get a 4xx with a JSON error naming the problem, and the server goes on",
          "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--max-body", "100000"}, dir.path());
    httplib::Client client("127.0.0.1", server.port());
    const auto error_of = [&](const httplib::Result& res, int status) {
        REQUIRE(res);
        CAPTURE(res->body);
        CHECK(res->status == status);
        return json::parse(res->body)["error"].get<std::string>();
    };
    const auto post_raw = [&](const std::string& path, const std::string& body) {
        return client.Post(path.c_str(), body, "application/json");
    };
    const std::vector<float> short_segment(10, 0.5f);
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", json{{"segments", {short_segment}}}.dump()), 400) ==
          "segments[0] has 10 values, the knowledge base expects 150");
    std::string with_text = json{{"segments", {std::vector<float>(150, 0.5f)}}}.dump();
    with_text.replace(with_text.find("0.5"), 3, "\"NaN\"");
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", with_text), 400) == "segments[0][0] is not a number");
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", "{\"segments\": [[1, 2"), 400).rfind("malformed JSON", 0) == 0);
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", "[]"), 400) == "the body must be a JSON object");
    CHECK(error_of(post_raw("/v1/kbs/run/shape", json{{"behaviour", json::array({std::vector<float>(15, 0.f)})}}.dump()), 400) ==
          "behaviour has 1 rows, fewer than one segment (10 rows)");
    CHECK(error_of(post_raw("/v1/kbs/nope/lookup", json{{"segments", json::array()}}.dump()), 404) ==
          "no knowledge base \"nope\" here");
    CHECK(error_of(post_raw("/v1/kbs/run/observe", json{{"policies", json::array()}}.dump()), 403).find("read-only") !=
          std::string::npos);
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", std::string(200000, ' ')), 413) == "the request body is too large");
    CHECK(error_of(client.Get("/v1/kbs/run/segments?order=bogus"), 400) == "order must be reward, count or id, got \"bogus\"");
    CHECK(error_of(client.Get("/v1/kbs/run/segments?limit=99999999"), 413) == "limit must be at most 10000");
    CHECK(error_of(client.Get("/v1/kbs/run/segments?limit=-3"), 400) == "limit must be a whole number >= 0, got \"-3\"");
    CHECK(error_of(client.Get("/v1/runs/7/generations"), 404) == "no run 7 here");
    CHECK(error_of(client.Get("/v1/nothing"), 404) == "no such endpoint: GET /v1/nothing");
    // an invalid UTF-8 byte in an unknown path: a 404 (the byte as U+FFFD), not a dead server
    CHECK(error_of(client.Get("/x%ff"), 404) == "no such endpoint: GET /x\xef\xbf\xbd");
    CHECK(error_of(client.Get("/v1/runs/99999999999999999999/generations"), 404) ==
          "no run 99999999999999999999 here");
    std::string huge = json{{"segments", {std::vector<float>(150, 0.5f)}}}.dump();
    huge.replace(huge.find("0.5"), 3, "1e400");
    CHECK(error_of(post_raw("/v1/kbs/run/lookup", huge), 400).rfind("unreadable JSON", 0) == 0);
    // an error echoes a bounded part of the input
    const auto long_name = error_of(client.Get(("/v1/kbs/" + std::string(5000, 'k')).c_str()), 404);
    CHECK(long_name.size() < 400);
    CHECK(get(client, "/healthz")["status"] == "ok");
    CHECK(server.stop() == 0);
}

TEST_CASE("concurrent clients get the answers of one client", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto base = load(dir / "run.db", "run");
    ServerProcess server({(dir / "run.db").string(), "--threads", "4"}, dir.path());
    std::vector<std::vector<std::vector<float>>> probes;
    std::vector<kb::Lookup> expected;
    for (unsigned k = 0; k < 8; ++k) {
        probes.push_back(probe_segments(base, 100 + k, 20));
        const auto values = flat(probes.back());
        expected.push_back(base.lookup(kb::as_segments(values, base.params().dim())));
    }
    std::vector<std::string> failures(4);
    std::vector<std::thread> clients;
    for (std::size_t t = 0; t < 4; ++t) {
        clients.emplace_back([&, t] {
            httplib::Client client("127.0.0.1", server.port());
            for (int round = 0; round < 10; ++round) {
                const std::size_t k = (t + static_cast<std::size_t>(round)) % probes.size();
                const auto res = client.Post("/v1/kbs/run/lookup", json{{"segments", probes[k]}}.dump(), "application/json");
                if (!res || res->status != 200) {
                    failures[t] = "request failed";
                    return;
                }
                const auto answer = json::parse(res->body);
                if (answer["r_max"].get<double>() != expected[k].r_max) failures[t] = "r_max differs";
                for (std::size_t i = 0; i < expected[k].segments.size(); ++i) {
                    if (answer["matches"][i]["distance"].get<double>() != expected[k].segments[i].distance) {
                        failures[t] = "a distance differs";
                    }
                }
            }
        });
    }
    for (auto& c : clients) c.join();
    for (const auto& f : failures) CHECK(f.empty());
    CHECK(server.stop() == 0);
}

TEST_CASE("observations need the token, are durable when answered and equal observing in process",
          "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db", true);  // every genome kept, to replay three of them
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()}).exit_code == 0);
    auto base = load(dir / "kb.db");
    test::write_file(dir / "token", "a-long-enough-secret-token\n");
    // three policies: stored behaviours of the run, with rewards of our own
    std::vector<std::vector<float>> behaviours;
    for (const auto* individual : {"best", "0", "3"})
        behaviours.push_back(runs::replay_behaviour(dir / "run.db", individual));
    const double rewards[] = {0.25, 0.5, 0.0};
    json policies = json::array();
    for (std::size_t i = 0; i < 3; ++i) policies.push_back({{"behaviour", rows_of(behaviours[i], 15)}, {"reward", rewards[i]}});
    const json body{{"run", "client"}, {"generation", 7}, {"policies", policies}};

    ServerProcess server({(dir / "kb.db").string(), "--writable", "--token-file", (dir / "token").string()}, dir.path());
    httplib::Client client("127.0.0.1", server.port());
    const auto refused = client.Post("/v1/kbs/run/observe", body.dump(), "application/json");
    REQUIRE(refused);
    CHECK(refused->status == 401);
    client.set_bearer_token_auth("wrong-token-of-some-length");
    CHECK(client.Post("/v1/kbs/run/observe", body.dump(), "application/json")->status == 401);
    client.set_bearer_token_auth("a-long-enough-secret-token");
    const auto answer = post(client, "/v1/kbs/run/observe", body);
    CHECK(answer["durable"] == true);
    CHECK(answer["observed"] == 3);
    // refused before anything is written (the comparison below would see it): rewards whose sum on one
    // segment would overflow to Inf, a run name with a NUL, a 1 MB run name
    const auto status_of = [&](const json& refused_body, const std::string& message) {
        const auto res = client.Post("/v1/kbs/run/observe", refused_body.dump(), "application/json");
        REQUIRE(res);
        CHECK(res->status == 400);
        CHECK_THAT(res->body, Catch::Matchers::Contains(message));
    };
    json huge = body;
    huge["policies"][0]["reward"] = 1e308;
    huge["policies"][1]["reward"] = 1e308;
    status_of(huge, "policies[0].reward must be a finite number within +-1e+289");
    json nul = body;
    nul["run"] = std::string("cli\0ent", 7);
    status_of(nul, "control character");
    json long_name = body;
    long_name["run"] = std::string(1 << 20, 'r');
    status_of(long_name, "1048576 bytes, more than 256");
    CHECK(server.stop() == 0);
    // the file is back in rollback-journal mode: neither the server nor a
    // later reader leaves -wal or -shm beside it
    CHECK_FALSE(std::filesystem::exists(dir / "kb.db-wal"));
    CHECK(test::run_cli({"kb", "stats", (dir / "kb.db").string()}).exit_code == 0);
    CHECK_FALSE(std::filesystem::exists(dir / "kb.db-wal"));
    CHECK_FALSE(std::filesystem::exists(dir / "kb.db-shm"));

    // the same observations in process, on the KB as it was
    const auto source = base.add_source("client");
    for (std::size_t i = 0; i < 3; ++i) {
        base.observe(kb::segment_behaviour(behaviours[i], 15, base.params().segment_width), rewards[i], {source, 7});
    }
    const auto stored = load(dir / "kb.db");
    REQUIRE(stored.size() == base.size());
    CHECK(answer["segments"].get<std::size_t>() == base.size());
    for (std::size_t id = 0; id < base.size(); ++id) {
        CAPTURE(id);
        CHECK(stored.record(id).count == base.record(id).count);
        CHECK(stored.record(id).cum_reward == base.record(id).cum_reward);
    }
    CHECK(std::equal(stored.values().begin(), stored.values().end(), base.values().begin()));
}

TEST_CASE("unsafe or bad serve options are refused before listening", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    test::write_file(dir / "short", "abc\n");
    const auto refused = [&](const std::vector<std::string>& extra, const std::string& message) {
        std::vector<std::string> args{"serve", (dir / "run.db").string()};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto result = test::run_cli(args);
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK(result.err_lines()[0].find(message) != std::string::npos);
    };
    refused({"--bind", "0.0.0.0"}, "--bind 0.0.0.0 is not loopback: give --token-file");
    refused({"--writable"}, "--writable needs --token-file");
    refused({"--token-file", (dir / "short").string()}, "the token must have at least 16 characters");
    refused({"--port", "70000"}, "--port must be within 0 to 65535");
    for (const char* timeout : {"-1", "0", "1e30", "nan"})
        refused({"--timeout", timeout}, "--timeout must be within 1 to 3600 seconds");
    refused({"--threads", "5000"}, "--threads must be within 1 to 1024");
    refused({"--threads", "0"}, "--threads must be within 1 to 1024, got 0");
    refused({"--connections", "0"}, "--connections must be within 1 to 4096, got 0");
    refused({"--connections", "5000"}, "--connections must be within 1 to 4096, got 5000");
    const auto missing = test::run_cli({"serve", (dir / "none.db").string()});
    CHECK(missing.exit_code == 2);
    CHECK(missing.err_lines().at(0).find("none.db: no such file or directory") != std::string::npos);
}

TEST_CASE("a second server on a port in use is refused in one line naming the port", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess first({(dir / "run.db").string()}, dir.path());
    const std::string port = std::to_string(first.port());
    const auto second =
        test::run_cli_within({"serve", (dir / "run.db").string(), "--port", port}, std::chrono::seconds(20));
    CHECK(second.exit_code == 1);  // -1 would mean it was listening (shared with SO_REUSEPORT) until killed
    REQUIRE(second.err_lines().size() == 1);
    CHECK_THAT(second.err_lines()[0], Catch::Matchers::Contains("cannot listen on 127.0.0.1:" + port));
    httplib::Client client("127.0.0.1", first.port());
    const auto health = client.Get("/healthz");
    REQUIRE(health);
    CHECK(health->status == 200);
    CHECK(first.stop() == 0);
}
