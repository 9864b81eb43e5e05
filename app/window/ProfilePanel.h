// The studio's Profile panel as both window hosts show it (Interactive.cpp for an L-system,
// app/cfdg/DesignWindow.cpp for a Context Free design): the hottest rules of the last counted run
// (ProfileReport.h's rows), with Run again. The hosts keep the rows and count only while the panel
// is open.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "app/common/ProfileReport.h"
#include "viewer/Window.h"

namespace lcjit::app {

inline constexpr const char* kProfilePanelTitle = "Profile";

// Whose rules: an L-system's (kinds by their initial, "p A(n) < B", and a column for the last
// step) or a design's (kinds in words, "rule Leaf 3"; `finished`: the shapes finished by kind).
enum class ProfiledRules { LSystem, Design };

viewer::Panel profilePanel(const std::vector<ProfileRow>& rows, ProfiledRules whose, const std::string& finished,
                           std::function<void()> runAgain);

}  // namespace lcjit::app
