# tests for the view page (authalic view, --html; docs/view.md): tests/cli/view.sh.
# The Chromium cases open three pages in headless Chromium with WebGL through SwiftShader, a few seconds
# each; they test the page (JavaScript), not C code, so the sanitizer build (AU_SANITIZE) runs only the
# writer's case, where the C writer makes and checks a page of a small mesh.
au_cli_test(view.writer view.sh writer)
if(NOT AU_SANITIZE)
  au_cli_test(view.page.sphere view.sh page bunny.obj sphere ellipsoid.obj)
  au_cli_test(view.page.disk view.sh page face.obj disk disk_bump.obj)
  au_cli_test(view.page.torus view.sh page bob.obj torus torus_r3.obj)
endif()
