#include <stdexcept>

#include "tracking/camera_file.h"
#include "tracking/camera_file_internal.h"

namespace hoof::tracking::detail {

std::unique_ptr<CameraFileSource> OpenTiff(const std::filesystem::path& path) {
  throw std::runtime_error(path.string() + ": TIFF files are not read yet");
}

}  // namespace hoof::tracking::detail
