#pragma once
// Keyboard, mouse and drop events from GLFW's callbacks, queued until the next frame handles
// them in order, so a tap shorter than a frame is never lost (glfwGetKey read once per frame
// misses it at a low frame rate).
//
// Installed before ImGui_ImplGlfw_InitForOpenGL(window, true): ImGui's backend then puts its
// own key, button, scroll and char callbacks over these and calls them first (its "previous
// user callbacks"), so ImGui still sees every event and the frame decides, with ImGui's
// WantCapture flags, which events move the camera. Cursor moves and file drops are ours alone
// (ImGui 1.86 polls the cursor itself).

#include <string>
#include <vector>

struct GLFWwindow;

namespace lb {

struct InputEvent {
  enum class Kind { key, button, cursor, scroll, drop };
  Kind kind = Kind::key;
  int code = 0;                    // key: GLFW_KEY_*; button: GLFW_MOUSE_BUTTON_*
  int action = 0;                  // GLFW_PRESS, GLFW_RELEASE or GLFW_REPEAT
  int mods = 0;                    // GLFW_MOD_* bits
  double x = 0.0, y = 0.0;         // cursor: window position (screen units); scroll: offsets
  std::vector<std::string> paths;  // drop: the files dropped onto the window
};

class WindowInput {
 public:
  // Installs the callbacks on `window` and takes its user pointer.
  explicit WindowInput(GLFWwindow* window);
  ~WindowInput();  // removes them
  WindowInput(const WindowInput&) = delete;
  WindowInput& operator=(const WindowInput&) = delete;

  // The events since the last call, oldest first.
  std::vector<InputEvent> take();

 private:
  static void push(GLFWwindow* window, InputEvent event);
  GLFWwindow* window_;
  std::vector<InputEvent> queue_;
};

}  // namespace lb
