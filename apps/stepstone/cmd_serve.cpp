// stepstone serve: knowledge bases, runs and campaigns as a JSON service with a dashboard

#include <charconv>
#include <cstdint>
#include <memory>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "service/service.hpp"

namespace stepstone::app {

namespace {

void add_serve_command(CLI::App& app) {
    auto options = std::make_shared<service::ServeOptions>();
    auto input = std::make_shared<std::string>();
    auto token = std::make_shared<std::string>();
    auto* cmd = app.add_subcommand(
        "serve", "Serve knowledge bases (lookup, shape, observe), runs and a live dashboard over HTTP/JSON");
    cmd->add_option("input", *input, "KB file, run file, or campaign directory")->required();
    cmd->add_option("--bind", options->bind, "Address to listen on (default 127.0.0.1; others need --token-file)");
    cmd->add_option("--port", options->port, "Port (default 8080; 0: any free port, printed)");
    auto* threads =
        cmd->add_option("--threads", options->threads,
                        "Requests doing KB work at once, 1 to 1024 (default: every core, at least 2)");
    cmd->add_option("--connections", options->connections,
                    "Connections open at once, 1 to 4096 (default 64); more wait to be accepted; slow "
                    "clients hold one each");
    cmd->add_flag("--writable", options->writable,
                  "Accept observations (POST /v1/kbs/NAME/observe); opens the files for writing; needs --token-file");
    cmd->add_option("--token-file", *token, "File whose first line is the bearer token every /v1 request must carry");
    cmd->add_option(
        "--timeout", options->timeout_seconds,
        "Seconds one request may take, from its first byte to the answer's last, 1 to 3600 (default 30)");
    // read as text: CLI11 reads "-1" into an unsigned as its largest value
    auto max_body = std::make_shared<std::string>();
    cmd->add_option("--max-body", *max_body,
                    "Largest request body in bytes, 1 to 1073741824 (default 67108864, 64 MiB)")
        ->type_name("BYTES");
    cmd->footer(example({"stepstone serve demo-out/campaign --port 8080   # then open http://127.0.0.1:8080/",
                         "curl -s http://127.0.0.1:8080/v1/kbs",
                         "stepstone serve kb.db --writable --token-file token.txt --port 9000"}));
    cmd->callback([options, input, token, threads, max_body] {
        // 0 is the default's "every core", not a value to give
        if (threads->count() > 0 && options->threads == 0)
            throw ConfigError("--threads must be within 1 to 1024, got 0");
        if (!max_body->empty()) {
            std::uint64_t bytes = 0;
            const auto* end = max_body->data() + max_body->size();
            const auto parsed = std::from_chars(max_body->data(), end, bytes);
            if (parsed.ec != std::errc() || parsed.ptr != end || bytes < 1 ||
                bytes > service::kMaxBodyLimit) {
                throw ConfigError(concat("--max-body must be within 1 to ", service::kMaxBodyLimit,
                                         " bytes, got ", *max_body));
            }
            options->limits.max_body_bytes = static_cast<std::size_t>(bytes);
        }
        options->input = *input;
        options->token_file = *token;
        service::serve(*options);
    });
}

const CommandRegistrar serve_registrar(70, add_serve_command);

}  // namespace

}  // namespace stepstone::app
