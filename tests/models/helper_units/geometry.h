// The helper unit's interface (found through -I, as with g++).
#pragma once
float scaled(float x);
extern int calls;
