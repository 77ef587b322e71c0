// A core header that reaches up into the backends: the layer check must
// refuse this tree (tests/CMakeLists.txt, layers.upward_include_fails).
#pragma once

#include "backend/thing.hpp"
