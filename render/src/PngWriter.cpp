#include "rgvc/render/PngWriter.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace rgvc {
namespace {

/// Where libpng's error callback leaves its message before longjmp-ing back.
struct PngErrorState {
    char message[256] = {};
};

extern "C" void rgvcPngError(png_structp png, png_const_charp msg) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    if (state != nullptr) {
        std::snprintf(state->message, sizeof state->message, "libpng: %s", msg != nullptr ? msg : "unknown error");
    }
    png_longjmp(png, 1); // never returns: back to the setjmp in encode()
}

extern "C" void rgvcPngWarning(png_structp, png_const_charp) {} // warnings are not errors; stay quiet

/// The libpng part, kept free of C++ objects with destructors: longjmp out of libpng lands in this
/// frame, and skipping a destructor there would be undefined behaviour. Everything it needs (the row
/// pointers) was allocated by the caller. Returns false with state.message set on a libpng error.
bool encode(std::FILE* fp, const ImageRGB& image, png_bytep* rows, PngErrorState& state) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, rgvcPngError, rgvcPngWarning);
    if (png == nullptr) {
        std::snprintf(state.message, sizeof state.message, "libpng: cannot create write struct");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (info == nullptr) {
        png_destroy_write_struct(&png, nullptr);
        std::snprintf(state.message, sizeof state.message, "libpng: cannot create info struct");
        return false;
    }
    // png and info are not modified between setjmp and a possible longjmp, so they need no volatile.
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, png_uint_32(image.width()), png_uint_32(image.height()), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
    throw std::runtime_error(path + ": " + reason);
}

} // namespace

void writePng(const std::string& path, const ImageRGB& image) {
    if (image.empty())
        fail(path, "cannot write an empty image (" + std::to_string(image.width()) + "x" +
                       std::to_string(image.height()) + ")");

    std::vector<png_bytep> rows(std::size_t(image.height()));
    for (int y = 0; y < image.height(); ++y)
        rows[std::size_t(y)] = const_cast<png_bytep>(image.data() + std::size_t(y) * image.stride());

    errno = 0;
    std::FILE* fp = std::fopen(path.c_str(), "wb");
    if (fp == nullptr) fail(path, std::string("cannot open for writing: ") + std::strerror(errno));

    PngErrorState state;
    bool ok = encode(fp, image, rows.data(), state);
    std::string reason = ok ? std::string() : std::string(state.message);
    if (ok && (std::fflush(fp) != 0 || std::ferror(fp))) {
        ok = false;
        reason = std::string("write failed: ") + std::strerror(errno);
    }
    if (std::fclose(fp) != 0 && ok) {
        ok = false;
        reason = std::string("close failed: ") + std::strerror(errno);
    }
    if (!ok) {
        std::remove(path.c_str());
        fail(path, reason);
    }
}

} // namespace rgvc
