#pragma once
// Keyboard, mouse and drop events from GLFW's callbacks, queued until the next frame handles
// them in order, so a tap shorter than a frame is never lost (glfwGetKey read once per frame
// misses it at a low frame rate).
//
// Installed after ImGui_ImplGlfw_InitForOpenGL(window, true): these callbacks replace the ones
// there were (ImGui's) and call them, so ImGui still sees every event, and the frame decides
// with ImGui's WantCapture flags which events move the camera. One change for ImGui 1.86,
// which reads key states once per frame: after a key pressed since the last frame, releases are
// passed on only at end_frame(), so ImGui sees the key down (and its modifiers with it) for a
// frame (Enter or Ctrl+A in a text field at 10 frames a second). Cursor moves and file drops are
// ours alone (ImGui 1.86 polls the cursor itself).

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
  // Installs the callbacks on `window` (keeping the ones there were) and takes its user
  // pointer.
  explicit WindowInput(GLFWwindow* window);
  ~WindowInput();  // puts the previous callbacks back
  WindowInput(const WindowInput&) = delete;
  WindowInput& operator=(const WindowInput&) = delete;

  // The events since the last call, oldest first.
  std::vector<InputEvent> take();
  // After each frame: passes on the key releases held back for it.
  void end_frame();

 private:
  using KeyCallback = void (*)(GLFWwindow*, int, int, int, int);
  using ButtonCallback = void (*)(GLFWwindow*, int, int, int);
  using PositionCallback = void (*)(GLFWwindow*, double, double);
  using DropCallback = void (*)(GLFWwindow*, int, const char**);
  struct HeldRelease {
    int key, scancode, mods;
  };
  static WindowInput* of(GLFWwindow* window);
  void key(int key, int scancode, int action, int mods);

  GLFWwindow* window_;
  std::vector<InputEvent> queue_;
  std::vector<int> pressed_this_frame_;  // keys pressed since the last end_frame()
  std::vector<HeldRelease> held_releases_;
  KeyCallback previous_key_ = nullptr;
  ButtonCallback previous_button_ = nullptr;
  PositionCallback previous_cursor_ = nullptr;
  PositionCallback previous_scroll_ = nullptr;
  DropCallback previous_drop_ = nullptr;
};

}  // namespace lb
