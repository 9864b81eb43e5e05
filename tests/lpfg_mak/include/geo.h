// The helper unit's interface, included by the model with its path.
#pragma once
float scaled(float x);
