// `serve`: KB lookups over loopback HTTP (stepstone serve's server, in
// process, on a free port) by N concurrent clients, against the same lookups
// made in process on one thread; one row a client count, serve/1, serve/2 and
// serve/8.

#include <httplib.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "bench/cases.hpp"
#include "core/error.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "kb/segments.hpp"
#include "service/service.hpp"
#include "sim/controllers.hpp"
#include "sim/episode.hpp"

namespace stepstone::bench {

namespace {

namespace fs = std::filesystem;

// a KB file of the segments of random policies, a server on it, and the
// batch of 200 segments (one policy's) that every request looks up
struct ServeState {
    fs::path dir;
    kb::KnowledgeBase kb{kb::KbParams{}};
    std::vector<float> batch;
    std::string body;
    std::unique_ptr<service::HttpServer> server;
    std::thread thread;
    std::vector<std::unique_ptr<httplib::Client>> clients;

    ~ServeState() {
        if (server) server->stop();
        if (thread.joinable()) thread.join();
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
};

std::shared_ptr<ServeState> make_state(Size size, int clients) {
    auto state = std::make_shared<ServeState>();
    state->dir = fs::temp_directory_path() /
                 ("stepstone-bench-serve-" + std::to_string(::getpid()) + "-" + std::to_string(clients));
    fs::remove_all(state->dir);
    fs::create_directories(state->dir);
    sim::TaskConfig config;
    config.starts = 1;
    const auto task = sim::make_task(config);
    std::vector<float> behaviour(task->behaviour_size());
    const auto source = state->kb.add_source("bench");
    const int policies = size == Size::full ? 160 : 8;
    for (int p = 0; p <= policies; ++p) {
        sim::RandomController random(static_cast<std::uint64_t>(p) + 1);
        sim::run_episode(*task, random, sim::Recording{behaviour, {}, nullptr});
        // the last policy is not observed: it is the one looked up
        if (p < policies) {
            state->kb.observe(kb::segment_behaviour(behaviour, sim::kChannels, 20), (p % 5) / 24.0,
                              {source, p});
        }
    }
    state->batch = behaviour;
    nlohmann::json segments = nlohmann::json::array();
    const auto cut = kb::segment_behaviour(behaviour, sim::kChannels, 20);
    for (std::size_t i = 0; i < cut.size(); ++i)
        segments.push_back(std::vector<float>(cut[i].begin(), cut[i].end()));
    state->body = nlohmann::json{{"segments", segments}}.dump();
    {
        auto connection = db::open_database(state->dir / "kb.db", db::OpenMode::create);
        db::Transaction transaction(connection);
        db::insert_kb(connection, "bench", state->kb);
        transaction.commit();
    }
    service::ServeOptions options;
    options.input = state->dir / "kb.db";
    options.port = 0;
    options.threads = static_cast<unsigned>(std::max(clients, 2));
    state->server = std::make_unique<service::HttpServer>(options);
    state->thread = std::thread([server = state->server.get()] { server->run(); });
    for (int c = 0; c < clients; ++c) {
        state->clients.push_back(std::make_unique<httplib::Client>("127.0.0.1", state->server->port()));
        state->clients.back()->set_keep_alive(true);
    }
    return state;
}

Workload serve_workload(Size size, int clients) {
    auto state = make_state(size, clients);
    Work in_process = [state] {
        const auto lookup = state->kb.lookup(kb::segment_behaviour(state->batch, sim::kChannels, 20));
        return static_cast<std::uint64_t>(lookup.segments.size());
    };
    Work over_http = [state] {
        std::vector<std::thread> threads;
        std::vector<int> ok(state->clients.size(), 0);
        for (std::size_t c = 0; c < state->clients.size(); ++c) {
            threads.emplace_back([&, c] {
                const auto res =
                    state->clients[c]->Post("/v1/kbs/bench/lookup", state->body, "application/json");
                ok[c] = res && res->status == 200;
            });
        }
        for (auto& t : threads) t.join();
        for (const int o : ok) {
            if (!o) throw DataError("bench serve: a lookup request failed");
        }
        return static_cast<std::uint64_t>(state->clients.size() * 200);
    };
    return Workload{in_process, over_http};
}

}  // namespace

void add_serve_cases(Registry& registry) {
    for (const int clients : {1, 2, 8}) {
        registry.add(Case{"serve/" + std::to_string(clients), "lookups",
                          "KB lookups of one policy's 200 segments (a KB of ~30,000) over loopback HTTP by " +
                              std::to_string(clients) + (clients == 1 ? " client" : " concurrent clients") +
                              " vs in process on one thread",
                          0.5, [clients](Size size) { return serve_workload(size, clients); }});
    }
}

}  // namespace stepstone::bench
