#include "viewer/window_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace lb {

namespace {

InputEvent make_event(InputEvent::Kind kind, int code, int action, int mods, double x = 0.0,
                      double y = 0.0) {
  InputEvent event;
  event.kind = kind;
  event.code = code;
  event.action = action;
  event.mods = mods;
  event.x = x;
  event.y = y;
  return event;
}

}  // namespace

WindowInput::WindowInput(GLFWwindow* window) : window_(window) {
  using Kind = InputEvent::Kind;
  glfwSetWindowUserPointer(window, this);
  previous_key_ =
      glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
        if (WindowInput* input = of(w)) input->key(key, scancode, action, mods);
      });
  previous_button_ =
      glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
        WindowInput* input = of(w);
        if (!input) return;
        if (input->previous_button_) input->previous_button_(w, button, action, mods);
        input->queue_.push_back(make_event(Kind::button, button, action, mods));
      });
  previous_cursor_ = glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    WindowInput* input = of(w);
    if (!input) return;
    if (input->previous_cursor_) input->previous_cursor_(w, x, y);
    input->queue_.push_back(make_event(Kind::cursor, 0, 0, 0, x, y));
  });
  previous_scroll_ = glfwSetScrollCallback(window, [](GLFWwindow* w, double x, double y) {
    WindowInput* input = of(w);
    if (!input) return;
    if (input->previous_scroll_) input->previous_scroll_(w, x, y);
    input->queue_.push_back(make_event(Kind::scroll, 0, 0, 0, x, y));
  });
  previous_drop_ = glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
    WindowInput* input = of(w);
    if (!input) return;
    if (input->previous_drop_) input->previous_drop_(w, count, paths);
    InputEvent event = make_event(Kind::drop, 0, 0, 0);
    event.paths.assign(paths, paths + count);
    input->queue_.push_back(std::move(event));
  });
}

WindowInput::~WindowInput() {
  end_frame();  // no release held back for ever
  glfwSetKeyCallback(window_, previous_key_);
  glfwSetMouseButtonCallback(window_, previous_button_);
  glfwSetCursorPosCallback(window_, previous_cursor_);
  glfwSetScrollCallback(window_, previous_scroll_);
  glfwSetDropCallback(window_, previous_drop_);
  glfwSetWindowUserPointer(window_, nullptr);
}

std::vector<InputEvent> WindowInput::take() {
  std::vector<InputEvent> events;
  events.swap(queue_);
  return events;
}

void WindowInput::end_frame() {
  pressed_this_frame_.clear();
  std::vector<HeldRelease> releases;
  releases.swap(held_releases_);
  if (previous_key_)
    for (const HeldRelease& r : releases)
      previous_key_(window_, r.key, r.scancode, GLFW_RELEASE, r.mods);
}

WindowInput* WindowInput::of(GLFWwindow* window) {
  return static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
}

void WindowInput::key(int key, int scancode, int action, int mods) {
  if (action == GLFW_PRESS) pressed_this_frame_.push_back(key);
  // Once a press waits for ImGui's next frame, every release after it waits too, so a
  // modifier stays down with the key it modifies (Ctrl+A sent as one burst).
  if (action == GLFW_RELEASE && !pressed_this_frame_.empty())
    held_releases_.push_back({key, scancode, mods});
  else if (previous_key_)
    previous_key_(window_, key, scancode, action, mods);
  queue_.push_back(make_event(InputEvent::Kind::key, key, action, mods));
}

}  // namespace lb
