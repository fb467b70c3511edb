// SPDX-License-Identifier: MIT
#include "io/exr_io.hpp"

#include "io/errors.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <exception>

namespace vplrender {

void write_exr(const std::string& path, const image_rgb& img,
               const std::vector<std::pair<std::string, std::string>>& attributes) {
  output_set set;
  write_exr(set, path, img, attributes);
  set.publish();
}

void write_exr(output_set& set, const std::string& path, const image_rgb& img,
               const std::vector<std::pair<std::string, std::string>>& attributes) {
  require_finite(img, path);
  set.write(path, [&](const std::string& temp) {
    try {
      Imf::Header header(img.width, img.height);
      header.compression() = Imf::ZIP_COMPRESSION;
      for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
      for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
      Imf::OutputFile file(temp.c_str(), header);
      Imf::FrameBuffer fb;
      char* base = reinterpret_cast<char*>(const_cast<float*>(img.rgb.data()));
      const std::size_t xs = 3 * sizeof(float), ys = xs * static_cast<std::size_t>(img.width);
      fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
      fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
      fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
      file.setFrameBuffer(fb);
      file.writePixels(img.height);
    } catch (const std::exception& e) {
      // OpenEXR reports a full disk as the errno text of its failed write.
      const std::string why = e.what();
      if (why.find("No space left on device") != std::string::npos)
        throw output_error(path + ": no space left on device (writing OpenEXR)");
      throw output_error(path + ": cannot write OpenEXR (" + why + ")");
    }
  });
}

image_rgb read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    for (const char* c : {"R", "G", "B"})
      if (!file.header().channels().findChannel(c))
        throw input_error(path + ": OpenEXR file has no channel " + c);
    image_rgb img(w, h);
    Imf::FrameBuffer fb;
    const std::size_t xs = 3 * sizeof(float), ys = xs * static_cast<std::size_t>(w);
    // Slices are addressed with absolute data-window coordinates: shift the base pointer back.
    char* base = reinterpret_cast<char*>(img.rgb.data()) - static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) -
                 static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
    fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0 * sizeof(float), xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + 1 * sizeof(float), xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return img;
  } catch (const input_error&) {
    throw;
  } catch (const std::exception& e) {
    throw input_error(path + ": cannot read OpenEXR (" + e.what() + ")");
  }
}

}  // namespace vplrender
