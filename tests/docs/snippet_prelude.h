#pragma once
// Included first by every documentation fragment (extract_snippets.py): the public headers the fragments in
// README.md and docs/*.md use without showing their includes. A program snippet includes what it uses itself.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_run.h"
#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "diagrams/stepping_stones/stepping_stones_run.h"
#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_run.h"
#include "framework/diagram.h"
#include "framework/linearize.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/classic/bouncing_ball.h"
#include "systems/controllers/lqr_controller.h"
