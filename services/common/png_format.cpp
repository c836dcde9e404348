#include "services/common/png_format.h"

#include <zlib.h>

#include <stdexcept>

#include "services/common/error.h"
#include "services/common/map_server_format.h"
#include "services/common/text_file.h"

namespace navd {
namespace {

void PutBigEndian(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((v >> shift) & 0xff));
}

// One PNG chunk: length, type, data, CRC of type and data.
void PutChunk(std::string& out, const char* type, const std::string& data) {
  PutBigEndian(out, static_cast<uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  PutBigEndian(out, static_cast<uint32_t>(
                        crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
}

}  // namespace

void SaveMapPng(const OccupancyGrid& grid, const std::string& path) {
  if (grid.empty()) throw Error(ErrorCode::kInvalidArgument, "map: cannot write an empty map as PNG");
  const std::vector<uint8_t> pixels = MapImage(grid);
  // Each row starts with filter type 0 (none).
  std::string raw;
  raw.reserve(static_cast<size_t>(grid.height()) * (grid.width() + 1));
  for (int row = 0; row < grid.height(); ++row) {
    raw.push_back('\0');
    raw.append(reinterpret_cast<const char*>(&pixels[static_cast<size_t>(row) * grid.width()]), grid.width());
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                static_cast<uLong>(raw.size()), Z_BEST_COMPRESSION) != Z_OK) {
    throw std::runtime_error(path + ": could not compress the image");
  }
  packed.resize(packed_size);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  PutBigEndian(header, static_cast<uint32_t>(grid.width()));
  PutBigEndian(header, static_cast<uint32_t>(grid.height()));
  header += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit greyscale, deflate, no filter, no interlace
  PutChunk(png, "IHDR", header);
  PutChunk(png, "IDAT", packed);
  PutChunk(png, "IEND", "");
  WriteFileAtomically(path, png);
}

}  // namespace navd
