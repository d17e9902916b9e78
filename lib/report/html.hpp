#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "report/canvas.hpp"

namespace stepstone::report {

/// A self-contained HTML page being written into a directory: its figures
/// are files beside it, its style is inline, it loads nothing else.
class Page {
public:
    /// Figures are written into `dir`, which must exist.
    Page(std::filesystem::path dir, std::string title);

    void heading(const std::string& text, int level = 2);
    /// A paragraph; `html` is inserted as is (escape with xml_escape).
    void paragraph(const std::string& html);
    void preformatted(const std::string& text);
    /// A table; cells are escaped. A row shorter than the header is padded.
    void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
               const std::string& caption = "");
    /// Draws a figure with `draw` into `name`.png (and `name`.svg when
    /// `interactive`: the page then shows the SVG, whose hover titles work,
    /// with the PNG as its fallback) and adds it with `caption`.
    void figure(const std::string& name, int width, int height, const std::string& caption,
                const std::function<void(Canvas&)>& draw, bool interactive = false);

    /// Files written so far, relative to the directory.
    const std::vector<std::string>& files() const { return files_; }
    /// The whole page.
    std::string html() const;

private:
    std::filesystem::path dir_;
    std::string title_;
    std::string body_;
    std::vector<std::string> files_;
};

/// Writes into a new directory `out` atomically: `fill` writes into a
/// temporary sibling directory, which is renamed to `out` once `fill`
/// returns. An existing `out` is refused (ConfigError) unless `force`, then
/// replaced only after `fill` succeeded. On any error nothing is left behind.
void write_directory(const std::filesystem::path& out, bool force,
                     const std::function<void(const std::filesystem::path&)>& fill);

}  // namespace stepstone::report
