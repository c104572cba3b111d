#pragma once
// The viewer page (runtime/src/view/page/): its HTML, style and script, compiled into the
// library from the files there (runtime/CMakeLists.txt writes view_page.cpp from them).
#include <string_view>

namespace phynjo::runtime::detail {
extern const std::string_view kViewerHtml;
extern const std::string_view kViewerCss;
extern const std::string_view kViewerJs;
} // namespace phynjo::runtime::detail
