// stepstone serve: knowledge bases, runs and campaigns as a JSON service with a dashboard

#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
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
    cmd->add_option(
        "--connections", options->connections,
        "Connections served at once, one thread each, 1 to 4096 (default 64); slow clients hold one each");
    cmd->add_flag("--writable", options->writable,
                  "Accept observations (POST /v1/kbs/NAME/observe); opens the files for writing; needs --token-file");
    cmd->add_option("--token-file", *token, "File whose first line is the bearer token every /v1 request must carry");
    cmd->add_option(
        "--timeout", options->timeout_seconds,
        "Seconds one request may take, from its first byte to the answer's last, 1 to 3600 (default 30)");
    cmd->add_option("--max-body", options->limits.max_body_bytes, "Largest request body in bytes (default 64 MiB)");
    cmd->footer(example({"stepstone serve demo-out/campaign --port 8080   # then open http://127.0.0.1:8080/",
                         "curl -s http://127.0.0.1:8080/v1/kbs",
                         "stepstone serve kb.db --writable --token-file token.txt --port 9000"}));
    cmd->callback([options, input, token, threads] {
        // 0 is the default's "every core", not a value to give
        if (threads->count() > 0 && options->threads == 0)
            throw ConfigError("--threads must be within 1 to 1024, got 0");
        options->input = *input;
        options->token_file = *token;
        service::serve(*options);
    });
}

const CommandRegistrar serve_registrar(70, add_serve_command);

}  // namespace

}  // namespace stepstone::app
