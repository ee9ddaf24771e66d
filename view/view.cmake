# view/view.cmake - the `authalic view` page compiled into the library (common/au_view.c).
# three.js comes from the npm registry, pinned by view/package-lock.json: `npm ci` installs it into the
# build directory (never the source tree), and view/embed.mjs makes AU_VIEW_PAGE_SOURCE, the page as C
# arrays. AU_THREE_JS names a three.module.min.js to use instead (a machine with no registry access).
# Sets AU_VIEW_SOURCES.
find_program(AU_NODE NAMES node nodejs)
if(NOT AU_NODE)
  message(FATAL_ERROR "authalic view needs Node.js (node) at build time: apt-get install nodejs npm (scripts/setup-debian.sh)")
endif()
set(AU_THREE_JS "" CACHE FILEPATH "three.module.min.js to inline in the view page (default: npm ci from view/package-lock.json)")
set(AU_VIEW_DIR ${CMAKE_CURRENT_SOURCE_DIR}/view)
if(AU_THREE_JS)
  set(AU_VIEW_THREE ${AU_THREE_JS})
else()
  find_program(AU_NPM npm)
  if(NOT AU_NPM)
    message(FATAL_ERROR "authalic view needs npm at build time (or -DAU_THREE_JS=.../three.module.min.js)")
  endif()
  set(AU_VIEW_NPM ${CMAKE_BINARY_DIR}/view-npm)
  set(AU_VIEW_THREE ${AU_VIEW_NPM}/node_modules/three/build/three.module.min.js)
  add_custom_command(OUTPUT ${AU_VIEW_THREE}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${AU_VIEW_NPM}
    COMMAND ${CMAKE_COMMAND} -E copy ${AU_VIEW_DIR}/package.json ${AU_VIEW_DIR}/package-lock.json ${AU_VIEW_NPM}
    COMMAND ${AU_NPM} ci --prefix ${AU_VIEW_NPM} --ignore-scripts --no-audit --no-fund --loglevel=error
    COMMAND ${CMAKE_COMMAND} -E touch ${AU_VIEW_THREE}
    DEPENDS ${AU_VIEW_DIR}/package.json ${AU_VIEW_DIR}/package-lock.json
    COMMENT "npm ci: three.js for the view page (view/package-lock.json)")
endif()
set(AU_VIEW_PAGE_SOURCE ${CMAKE_BINARY_DIR}/au_view_page.c)
add_custom_command(OUTPUT ${AU_VIEW_PAGE_SOURCE}
  COMMAND ${AU_NODE} ${AU_VIEW_DIR}/embed.mjs ${AU_VIEW_DIR} ${AU_VIEW_THREE} ${AU_VIEW_PAGE_SOURCE}
  DEPENDS ${AU_VIEW_DIR}/embed.mjs ${AU_VIEW_DIR}/page.html ${AU_VIEW_DIR}/view.js ${AU_VIEW_DIR}/view.css ${AU_VIEW_THREE}
  COMMENT "the view page: view/ and three.js as C arrays")
set(AU_VIEW_SOURCES common/au_view.c ${AU_VIEW_PAGE_SOURCE})
