#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "report/style.hpp"

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace stepstone::report {

/// The two output formats; the same drawing code makes both.
enum class Format { png, svg };

/// The format named by a file's extension (.png or .svg, any case); throws
/// ConfigError naming the path otherwise.
Format format_of(const std::filesystem::path& path);

/// A drawing surface in pixels (origin top left, y down) backed by cairo: an
/// image surface for PNG, a recording SVG surface for SVG (text drawn as
/// glyph outlines, so an SVG needs no font). Hover notes (SVG only) become
/// invisible circles carrying a <title>, which a browser shows on hover.
class Canvas {
public:
    Canvas(int width, int height, Format format);
    ~Canvas();
    Canvas(const Canvas&) = delete;
    Canvas& operator=(const Canvas&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    Format format() const { return format_; }
    /// The cairo context, for drawing not covered below.
    cairo_t* cr() const { return cr_; }

    void fill(Colour colour);
    void set_colour(Colour colour, double alpha = 1.0);
    /// Text with its anchor at (x, y): `align_x` 0 = left, 0.5 = centre, 1 = right
    /// of x; `align_y` likewise from the top of the text. Rotated by `angle`
    /// radians around the anchor (-pi/2 for a vertical axis label).
    void text(double x, double y, std::string_view text, double size, Colour colour, double align_x = 0.0,
              double align_y = 0.0, bool bold = false, double angle = 0.0);
    /// Width of `text` in pixels at `size`.
    double text_width(std::string_view text, double size, bool bold = false) const;

    /// Adds a hover note: a circle of radius `r` at (x, y) whose title is `title` (SVG only).
    void hover(double x, double y, double r, std::string title);

    /// The finished file's bytes (PNG or SVG). Call once, after drawing.
    std::string finish();
    /// finish() written to `path` atomically; an existing file is refused
    /// (ConfigError) unless `force`.
    void save(const std::filesystem::path& path, bool force);

private:
    struct Note {
        double x, y, r;
        std::string title;
    };
    int width_;
    int height_;
    Format format_;
    std::string svg_;  // the SVG surface's output, appended to as cairo writes it
    cairo_surface_t* surface_ = nullptr;
    cairo_t* cr_ = nullptr;
    std::vector<Note> notes_;
    bool finished_ = false;
};

/// Escapes &, <, >, " and ' for XML text and attributes.
std::string xml_escape(std::string_view text);

}  // namespace stepstone::report
