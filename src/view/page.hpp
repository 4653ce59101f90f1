#pragma once
// Internal: the page template built from web/ (web/build.mjs), with the
// placeholders <!--LAGRANGIAN-TITLE--> (twice), -DESCRIPTION-, -LEGEND- and
// -DATA-; empty when the library was built without it.

#include <string_view>

namespace lagrangian::view::detail {

extern const std::string_view page_template;

}  // namespace lagrangian::view::detail
