// The live view's window (`asf run --gui`): an MRPT window showing the pictures the pipeline
// renders. A library of its own, loaded only with --gui (cmd_run.cpp): MRPT's GUI brings
// wxWidgets and GTK, which no other command needs to load.
#include <mrpt/gui/CDisplayWindow.h>
#include <mrpt/img/CImage.h>

#include <memory>
#include <string>

extern "C" {

__attribute__((visibility("default"))) void* asf_live_window_open(const char* title) {
  return new mrpt::gui::CDisplayWindow(title);
}

__attribute__((visibility("default"))) void asf_live_window_show(void* window, int width,
                                                                 int height,
                                                                 const unsigned char* bgr) {
  auto* w = static_cast<mrpt::gui::CDisplayWindow*>(window);
  // The window takes the picture's size (1:1 pixels) when the picture's size changes.
  static thread_local int last_w = 0, last_h = 0;
  if (width != last_w || height != last_h) {
    w->resize(static_cast<unsigned>(width), static_cast<unsigned>(height));
    last_w = width, last_h = height;
  }
  mrpt::img::CImage img;
  img.loadFromMemoryBuffer(static_cast<unsigned>(width), static_cast<unsigned>(height), true,
                           const_cast<unsigned char*>(bgr));  // BGR rows, copied
  w->showImage(img);
}

__attribute__((visibility("default"))) int asf_live_window_is_open(void* window) {
  return static_cast<mrpt::gui::CDisplayWindow*>(window)->isOpen() ? 1 : 0;
}

__attribute__((visibility("default"))) void asf_live_window_close(void* window) {
  delete static_cast<mrpt::gui::CDisplayWindow*>(window);
}
}
