#include "exr_output.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <exception>

#include "error.h"

namespace rtsdf {

void write_exr(const std::string& path, const RenderOutput& output) {
  const size_t pixels = size_t(output.width) * size_t(output.height);
  if (pixels == 0 || output.combined.size() != 4 * pixels || output.depth.size() != pixels ||
      output.shadow.size() != pixels)
    throw Error("write_exr: the render output is empty or incomplete");
  try {
    Imf::Header header(output.width, output.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    const char* rgba[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
      header.channels().insert(rgba[c], Imf::Channel(Imf::FLOAT));
      frame.insert(rgba[c], Imf::Slice(Imf::FLOAT, (char*)(output.combined.data() + c), 4 * sizeof(float),
                                       4 * sizeof(float) * size_t(output.width)));
    }
    header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    frame.insert("Z", Imf::Slice(Imf::FLOAT, (char*)output.depth.data(), sizeof(float),
                                 sizeof(float) * size_t(output.width)));
    header.channels().insert("Shadow", Imf::Channel(Imf::FLOAT));
    frame.insert("Shadow", Imf::Slice(Imf::FLOAT, (char*)output.shadow.data(), sizeof(float),
                                      sizeof(float) * size_t(output.width)));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(output.height);  // rows top to bottom, as EXR stores them
  } catch (const std::exception& e) {
    throw Error("cannot write " + path + ": " + e.what());
  }
}

}  // namespace rtsdf
