#pragma once
// The one place the OpenGL loader is included. Code outside viewer/ never sees GL.
#include <glad/gl.h>
