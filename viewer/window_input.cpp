#include "viewer/window_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace lb {

WindowInput::WindowInput(GLFWwindow* window) : window_(window) {
  glfwSetWindowUserPointer(window, this);
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
    InputEvent event;
    event.kind = InputEvent::Kind::key;
    event.code = key;
    event.action = action;
    event.mods = mods;
    push(w, std::move(event));
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    InputEvent event;
    event.kind = InputEvent::Kind::button;
    event.code = button;
    event.action = action;
    event.mods = mods;
    push(w, std::move(event));
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    InputEvent event;
    event.kind = InputEvent::Kind::cursor;
    event.x = x;
    event.y = y;
    push(w, std::move(event));
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double x, double y) {
    InputEvent event;
    event.kind = InputEvent::Kind::scroll;
    event.x = x;
    event.y = y;
    push(w, std::move(event));
  });
  glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
    InputEvent event;
    event.kind = InputEvent::Kind::drop;
    event.paths.assign(paths, paths + count);
    push(w, std::move(event));
  });
}

WindowInput::~WindowInput() {
  glfwSetKeyCallback(window_, nullptr);
  glfwSetMouseButtonCallback(window_, nullptr);
  glfwSetCursorPosCallback(window_, nullptr);
  glfwSetScrollCallback(window_, nullptr);
  glfwSetDropCallback(window_, nullptr);
  glfwSetWindowUserPointer(window_, nullptr);
}

std::vector<InputEvent> WindowInput::take() {
  std::vector<InputEvent> events;
  events.swap(queue_);
  return events;
}

void WindowInput::push(GLFWwindow* window, InputEvent event) {
  if (auto* input = static_cast<WindowInput*>(glfwGetWindowUserPointer(window)))
    input->queue_.push_back(std::move(event));
}

}  // namespace lb
