// The page template, bundled at build time (web/build.mjs).

#include "page.hpp"

namespace lagrangian::view::detail {

#ifdef LAGRANGIAN_ANIMATION_PAGE
const std::string_view page_template =
#include "animation_page.inc"
    ;
#else
const std::string_view page_template;
#endif

}  // namespace lagrangian::view::detail
