// The cairo surface every figure draws on, written as PNG or SVG.

#include "report/canvas.hpp"

#include <cairo-svg.h>
#include <cairo.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"

namespace stepstone::report {

namespace {

cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

void check(cairo_status_t status, const char* what) {
    if (status != CAIRO_STATUS_SUCCESS) {
        throw Error(concat("cairo: ", what, ": ", cairo_status_to_string(status)));
    }
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", value);
    return text;
}

// PNG of an opaque ARGB32 cairo surface, through libpng: RGB rows, zlib level
// 3 and the "sub" filter, several times faster than cairo's own writer (level
// 6, every filter tried) for a file a few percent larger
std::string encode_png(cairo_surface_t* surface) {
    cairo_surface_flush(surface);
    const int width = cairo_image_surface_get_width(surface);
    const int height = cairo_image_surface_get_height(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    std::string out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        throw Error("libpng: out of memory");
    }
    std::vector<unsigned char> row(static_cast<std::size_t>(width) * 3);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw Error("libpng: could not encode the figure");
    }
    png_set_write_fn(
        png, &out,
        [](png_structp p, png_bytep bytes, png_size_t length) {
            static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<const char*>(bytes), length);
        },
        nullptr);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 3);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) {
        const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
        for (int x = 0; x < width; ++x) {
            // every figure paints an opaque background, so no unpremultiplying
            const std::uint32_t p = pixels[x];
            row[static_cast<std::size_t>(x) * 3] = static_cast<unsigned char>(p >> 16);
            row[static_cast<std::size_t>(x) * 3 + 1] = static_cast<unsigned char>(p >> 8);
            row[static_cast<std::size_t>(x) * 3 + 2] = static_cast<unsigned char>(p);
        }
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

// selects the figure font at `size` (inside the caller's save/restore) and measures `text`
cairo_text_extents_t measure(cairo_t* cr, const std::string& text, double size, bool bold) {
    cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t extents;
    cairo_text_extents(cr, text.c_str(), &extents);
    return extents;
}

}  // namespace

Format format_of(const std::filesystem::path& path) {
    auto extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension == ".png") return Format::png;
    if (extension == ".svg") return Format::svg;
    throw ConfigError(concat(path.string(), ": the figure's file name must end in .png or .svg"));
}

std::string xml_escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

Canvas::Canvas(int width, int height, Format format) : width_(width), height_(height), format_(format) {
    if (width < 1 || height < 1) throw std::invalid_argument("Canvas: empty size");
    if (format == Format::png) {
        surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    } else {
        surface_ = cairo_svg_surface_create_for_stream(append_bytes, &svg_, width, height);
        cairo_svg_surface_set_document_unit(surface_, CAIRO_SVG_UNIT_PX);
    }
    check(cairo_surface_status(surface_), "creating a surface");
    cr_ = cairo_create(surface_);
    check(cairo_status(cr_), "creating a context");
    cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
}

Canvas::~Canvas() {
    if (cr_ != nullptr) cairo_destroy(cr_);
    if (surface_ != nullptr) cairo_surface_destroy(surface_);
}

void Canvas::fill(Colour colour) {
    set_colour(colour);
    cairo_paint(cr_);
}

void Canvas::set_colour(Colour colour, double alpha) {
    cairo_set_source_rgba(cr_, colour.r, colour.g, colour.b, alpha);
}


void Canvas::text(double x, double y, std::string_view text, double size, Colour colour, double align_x,
                  double align_y, bool bold, double angle) {
    const std::string owned(text);
    cairo_save(cr_);
    const auto extents = measure(cr_, owned, size, bold);
    cairo_font_extents_t font;
    cairo_font_extents(cr_, &font);
    cairo_translate(cr_, x, y);
    cairo_rotate(cr_, angle);
    // vertical placement from the font's ascent, so labels of one row align
    cairo_move_to(cr_, -extents.x_advance * align_x, font.ascent - (font.ascent + font.descent) * align_y);
    set_colour(colour);
    cairo_show_text(cr_, owned.c_str());
    cairo_restore(cr_);
}

double Canvas::text_width(std::string_view text, double size, bool bold) const {
    cairo_save(cr_);
    const auto extents = measure(cr_, std::string(text), size, bold);
    cairo_restore(cr_);
    return extents.x_advance;
}

void Canvas::hover(double x, double y, double r, std::string title) {
    if (format_ == Format::svg) notes_.push_back({x, y, r, std::move(title)});
}

std::string Canvas::finish() {
    if (finished_) throw std::logic_error("Canvas::finish called twice");
    finished_ = true;
    check(cairo_status(cr_), "drawing");
    if (format_ == Format::png) return encode_png(surface_);
    cairo_destroy(cr_);
    cr_ = nullptr;
    cairo_surface_finish(surface_);
    check(cairo_surface_status(surface_), "writing SVG");
    if (notes_.empty()) return svg_;
    // the hover layer: transparent circles (still hit by the pointer) with titles
    std::string layer = "<g id=\"hover\" fill=\"#000\" fill-opacity=\"0\">\n";
    for (const auto& note : notes_) {
        layer += concat("<circle cx=\"", number(note.x), "\" cy=\"", number(note.y), "\" r=\"", number(note.r),
                        "\"><title>", xml_escape(note.title), "</title></circle>\n");
    }
    layer += "</g>\n";
    const auto end = svg_.rfind("</svg>");
    if (end == std::string::npos) throw Error("cairo: the SVG output has no </svg>");
    svg_.insert(end, layer);
    return svg_;
}

void Canvas::save(const std::filesystem::path& path, bool force) {
    const std::string bytes = finish();
    OutputFile out(path, force);
    out.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.commit();
}

}  // namespace stepstone::report
