#include "images.hpp"

#include <cairo.h>
#include <expat.h>

#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

namespace stepstone::reporttest {

namespace {

struct Reader {
    const std::string* bytes;
    std::size_t offset = 0;
};

cairo_status_t read_bytes(void* closure, unsigned char* data, unsigned int length) {
    auto* reader = static_cast<Reader*>(closure);
    if (reader->offset + length > reader->bytes->size()) return CAIRO_STATUS_READ_ERROR;
    std::memcpy(data, reader->bytes->data() + reader->offset, length);
    reader->offset += length;
    return CAIRO_STATUS_SUCCESS;
}

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
}

}  // namespace

bool png_signature(const std::string& bytes) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return bytes.size() >= 8 && std::memcmp(bytes.data(), signature, 8) == 0;
}

std::pair<std::uint32_t, std::uint32_t> png_size(const std::string& bytes) {
    // signature, then the IHDR chunk: length (4), "IHDR", width, height
    if (bytes.size() < 24 || bytes.compare(12, 4, "IHDR") != 0) throw std::runtime_error("no IHDR chunk first");
    return {big_endian(bytes, 16), big_endian(bytes, 20)};
}

Rgb Image::at(int x, int y) const {
    const std::uint32_t p = argb.at(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                    static_cast<std::size_t>(x));
    return {static_cast<int>((p >> 16) & 0xff), static_cast<int>((p >> 8) & 0xff), static_cast<int>(p & 0xff)};
}

std::size_t Image::colours() const { return std::set<std::uint32_t>(argb.begin(), argb.end()).size(); }

double Image::inked() const {
    std::size_t n = 0;
    for (const auto p : argb) n += (p & 0xffffff) != 0xffffff;
    return argb.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(argb.size());
}

Rgb rgb(report::Colour c) {
    return {static_cast<int>(std::lround(c.r * 255)), static_cast<int>(std::lround(c.g * 255)),
            static_cast<int>(std::lround(c.b * 255))};
}

Image decode_png(const std::string& bytes) {
    Reader reader{&bytes};
    cairo_surface_t* surface = cairo_image_surface_create_from_png_stream(read_bytes, &reader);
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(surface);
        throw std::runtime_error("not a decodable PNG");
    }
    // as ARGB32, whatever format the file had
    Image image;
    image.width = cairo_image_surface_get_width(surface);
    image.height = cairo_image_surface_get_height(surface);
    cairo_surface_t* argb = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, image.width, image.height);
    cairo_t* cr = cairo_create(argb);
    cairo_set_source_surface(cr, surface, 0, 0);
    cairo_paint(cr);
    cairo_destroy(cr);
    cairo_surface_flush(argb);
    const auto stride = static_cast<std::size_t>(cairo_image_surface_get_stride(argb));
    const unsigned char* data = cairo_image_surface_get_data(argb);
    image.argb.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
    for (int y = 0; y < image.height; ++y) {
        std::memcpy(&image.argb[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width)],
                    data + static_cast<std::size_t>(y) * stride, static_cast<std::size_t>(image.width) * 4);
    }
    cairo_surface_destroy(argb);
    cairo_surface_destroy(surface);
    return image;
}

namespace {

struct SvgState {
    SvgFacts facts;
    int depth = 0;
    bool in_title = false;
};

void XMLCALL on_start(void* data, const XML_Char* name, const XML_Char**) {
    auto* state = static_cast<SvgState*>(data);
    if (state->depth == 0) state->facts.root = name;
    ++state->depth;
    ++state->facts.elements;
    if (std::strcmp(name, "title") == 0) {
        ++state->facts.titles;
        state->facts.title_texts.emplace_back();
        state->in_title = true;
    }
}

void XMLCALL on_end(void* data, const XML_Char* name) {
    auto* state = static_cast<SvgState*>(data);
    --state->depth;
    if (std::strcmp(name, "title") == 0) state->in_title = false;
}

void XMLCALL on_text(void* data, const XML_Char* text, int length) {
    auto* state = static_cast<SvgState*>(data);
    if (state->in_title) state->facts.title_texts.back().append(text, static_cast<std::size_t>(length));
}

}  // namespace

SvgFacts parse_svg(const std::string& text) {
    SvgState state;
    XML_Parser parser = XML_ParserCreate(nullptr);
    XML_SetUserData(parser, &state);
    XML_SetElementHandler(parser, on_start, on_end);
    XML_SetCharacterDataHandler(parser, on_text);
    if (XML_Parse(parser, text.data(), static_cast<int>(text.size()), 1) == XML_STATUS_OK) {
        state.facts.well_formed = true;
    } else {
        state.facts.error = XML_ErrorString(XML_GetErrorCode(parser));
    }
    XML_ParserFree(parser);
    return state.facts;
}

std::string check_png(const std::string& bytes, int width, int height) {
    if (!png_signature(bytes)) return "no PNG signature";
    const auto [w, h] = png_size(bytes);
    if (static_cast<int>(w) != width || static_cast<int>(h) != height) {
        return "IHDR says " + std::to_string(w) + " x " + std::to_string(h);
    }
    const auto image = decode_png(bytes);
    if (image.inked() < 0.02) return "blank: " + std::to_string(image.inked()) + " of the pixels inked";
    if (image.colours() < 8) return "only " + std::to_string(image.colours()) + " colours";
    return "";
}

std::string check_svg(const std::string& text) {
    const auto facts = parse_svg(text);
    if (!facts.well_formed) return "not well-formed XML: " + facts.error;
    if (facts.root != "svg") return "root element is " + facts.root;
    if (facts.elements < 20) return "only " + std::to_string(facts.elements) + " elements";
    return "";
}

}  // namespace stepstone::reporttest
