// The HTML page of a report and its atomic output directory.

#include "report/html.hpp"

#include <unistd.h>

#include <fstream>
#include <system_error>

#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"

namespace stepstone::report {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStyle = R"(
body { font-family: "DejaVu Sans", sans-serif; max-width: 860px; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ddd; padding-bottom: 0.2em; }
h3 { font-size: 1.05em; margin-top: 1.5em; }
figure { margin: 1.2em 0; }
figure img, figure object { width: 100%; max-width: 800px; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.9em; color: #444; margin-top: 0.3em; }
table { border-collapse: collapse; font-size: 0.88em; margin: 0.8em 0; }
caption { text-align: left; font-size: 0.95em; color: #444; padding-bottom: 0.3em; }
th, td { border: 1px solid #ddd; padding: 0.25em 0.6em; text-align: right; }
th { background: #f4f4f4; }
td:first-child, th:first-child { text-align: left; }
pre { background: #f7f7f7; border: 1px solid #e5e5e5; padding: 0.7em; overflow-x: auto; font-size: 0.82em; }
.note { color: #8a4b00; }
)";

}  // namespace

Page::Page(fs::path dir, std::string title) : dir_(std::move(dir)), title_(std::move(title)) {}

void Page::heading(const std::string& text, int level) {
    body_ += concat("<h", level, ">", xml_escape(text), "</h", level, ">\n");
}

void Page::paragraph(const std::string& html) { body_ += concat("<p>", html, "</p>\n"); }

void Page::preformatted(const std::string& text) { body_ += concat("<pre>", xml_escape(text), "</pre>\n"); }

void Page::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                 const std::string& caption) {
    body_ += "<table>\n";
    if (!caption.empty()) body_ += concat("<caption>", xml_escape(caption), "</caption>\n");
    body_ += "<tr>";
    for (const auto& h : header) body_ += concat("<th>", xml_escape(h), "</th>");
    body_ += "</tr>\n";
    for (const auto& row : rows) {
        body_ += "<tr>";
        for (std::size_t i = 0; i < header.size(); ++i) {
            body_ += concat("<td>", i < row.size() ? xml_escape(row[i]) : std::string(), "</td>");
        }
        body_ += "</tr>\n";
    }
    body_ += "</table>\n";
}

void Page::figure(const std::string& name, int width, int height, const std::string& caption,
                  const std::function<void(Canvas&)>& draw, bool interactive) {
    {
        Canvas png(width, height, Format::png);
        draw(png);
        png.save(dir_ / (name + ".png"), false);
        files_.push_back(name + ".png");
    }
    const std::string alt = xml_escape(caption);
    body_ += "<figure>\n";
    if (interactive) {
        Canvas svg(width, height, Format::svg);
        draw(svg);
        svg.save(dir_ / (name + ".svg"), false);
        files_.push_back(name + ".svg");
        body_ += concat("<object type=\"image/svg+xml\" data=\"", name, ".svg\" width=\"", width, "\" height=\"",
                        height, "\"><img src=\"", name, ".png\" alt=\"", alt, "\"></object>\n");
    } else {
        body_ += concat("<img src=\"", name, ".png\" width=\"", width, "\" height=\"", height, "\" alt=\"", alt,
                        "\">\n");
    }
    body_ += concat("<figcaption>", alt, "</figcaption>\n</figure>\n");
}

std::string Page::html() const {
    return concat("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>", xml_escape(title_),
                  "</title>\n<style>", kStyle, "</style>\n</head>\n<body>\n<h1>", xml_escape(title_), "</h1>\n", body_,
                  "</body>\n</html>\n");
}

void write_directory(const fs::path& out, bool force, const std::function<void(const fs::path&)>& fill) {
    std::error_code error;
    const bool exists = fs::exists(out, error);
    if (exists && !force)
        throw ConfigError(concat(out.string(), " exists (use ", option_name("force"), " to replace it)"));
    if (exists && !fs::is_directory(out)) throw ConfigError(concat(out.string(), " exists and is not a directory"));
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, error)) {
        // the folder it goes in must exist: say which of the two it is
        throw ConfigError(concat("cannot write ", out.string(), ": ", parent.string(),
                                 fs::exists(parent, error) ? " is not a directory" : " does not exist"));
    }
    const fs::path temp = parent / concat(".", out.filename().string(), ".tmp-", ::getpid());
    fs::remove_all(temp, error);
    if (!fs::create_directory(temp, error)) {
        throw Error(concat("cannot write ", out.string(), ": ", error.message()));
    }
    try {
        fill(temp);
        if (exists) {
            const fs::path old = parent / concat(".", out.filename().string(), ".old-", ::getpid());
            fs::rename(out, old);
            fs::rename(temp, out);
            fs::remove_all(old, error);
        } else {
            fs::rename(temp, out);
        }
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(temp, error);
        throw Error(concat("cannot write ", out.string(), ": ", e.code().message()));
    } catch (...) {
        fs::remove_all(temp, error);
        throw;
    }
}

}  // namespace stepstone::report
