#include "synth/contact_sheet.h"

#include <cstdio>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace hoof::synth {

cv::Mat MakeContactSheet(const std::vector<ContactSheetRow>& rows, double scale) {
  constexpr int kGap = 4, kLabel = 22;
  std::vector<std::vector<cv::Mat>> tiles;
  int tile_w = 0, tile_h = 0, cols = 0;
  for (const ContactSheetRow& row : rows) {
    std::vector<cv::Mat> line;
    for (int i = row.first; i < row.first + row.count; ++i) {
      char name[32];
      std::snprintf(name, sizeof(name), "%06d.png", i);
      const auto path = row.trial_dir / "frames" / name;
      cv::Mat img = cv::imread(path.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
      if (img.empty()) throw std::runtime_error("cannot read frame '" + path.string() + "'");
      if (img.depth() == CV_16U) img.convertTo(img, CV_8U, 1.0 / 257);
      cv::resize(img, img, cv::Size(), scale, scale, cv::INTER_AREA);
      tile_w = std::max(tile_w, img.cols);
      tile_h = std::max(tile_h, img.rows);
      line.push_back(img);
    }
    cols = std::max(cols, static_cast<int>(line.size()));
    tiles.push_back(line);
  }
  const int rows_n = static_cast<int>(tiles.size());
  cv::Mat sheet(rows_n * (tile_h + kLabel + kGap) + kGap, cols * (tile_w + kGap) + kGap, CV_8U,
                cv::Scalar(255));
  for (int r = 0; r < rows_n; ++r) {
    const int y = kGap + r * (tile_h + kLabel + kGap);
    cv::putText(sheet, rows[r].label, cv::Point(kGap, y + kLabel - 6), cv::FONT_HERSHEY_SIMPLEX,
                0.5, cv::Scalar(0), 1, cv::LINE_AA);
    for (int c = 0; c < static_cast<int>(tiles[r].size()); ++c) {
      const int x = kGap + c * (tile_w + kGap);
      tiles[r][c].copyTo(sheet(cv::Rect(x, y + kLabel, tiles[r][c].cols, tiles[r][c].rows)));
      cv::putText(sheet, "frame " + std::to_string(rows[r].first + c),
                  cv::Point(x + 4, y + kLabel + 14), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255),
                  1, cv::LINE_AA);
    }
  }
  return sheet;
}

}  // namespace hoof::synth
