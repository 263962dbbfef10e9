#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace fleetnav::server::http {

/// One file of the dashboard (server/http/assets), compiled into the binary.
struct DashboardAsset {
  std::string path;  ///< "/index.html", "/app.js", ...
  std::string_view content;
  std::string_view content_type;
};

/// Every dashboard file; generated at build time from server/http/assets (cmake/EmbedFiles.cmake).
const std::vector<DashboardAsset>& DashboardAssets();

}  // namespace fleetnav::server::http
