// The simulator's input, one frame at a time, from the window (GLFW) or from a script, or both merged.
//
// Script files (`--script FILE`) drive the viewer so that the docs and the tests can. One event a line,
// `FRAME EVENT ARGS...`, FRAME the 0-based frame it happens at; '#' starts a comment; blank lines are
// skipped. Coordinates are window pixels, (0, 0) the top-left corner.
//
//   F key NAME        tap NAME at frame F: pressed and released (toggles, pause, shape choice)
//   F hold NAME N     hold NAME down for N >= 1 frames from F (movement and turning keys)
//   F mouse X Y       the cursor moves to (X, Y)
//   F click X Y       the left button goes down and up at (X, Y): spawns the chosen shape, or grabs
//   F press X Y       the left button goes down at (X, Y) (a drag: press, mouse ..., release)
//   F release X Y     the left button goes up at (X, Y)
//   F look DX         mouse look: turn as if the mouse moved DX pixels with the right button held
//   F wheel DY        the wheel turns DY notches (positive: narrower field of view)
//   F quit            the run ends after frame F
//
// Key names: a-z, 0-9, space, tab, escape, left, right, up, down (KEYS in the README).
#pragma once

#include "rgvc/grid/Math.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace rgvc::sim {

/// The keys the simulator knows. Letters and digits, then the named ones.
enum class Key : int {
    A = 0, // ... Z = 25
    Num0 = 26, // ... Num9 = 35
    Space = 36,
    Tab,
    Escape,
    Left,
    Right,
    Up,
    Down,
    Count
};
inline constexpr int kKeyCount = int(Key::Count);
inline Key letterKey(char c) { return Key(c - 'a'); }
inline Key digitKey(int d) { return Key(int(Key::Num0) + d); }

/// "a", "7", "space", ...; parseKey is its inverse (lower case only).
std::string keyName(Key k);
std::optional<Key> parseKey(const std::string& name);

/// The input of one frame.
struct InputFrame {
    std::array<bool, kKeyCount> down{};   ///< held during the frame
    std::vector<Key> pressed;             ///< went down this frame (a tap counts)
    std::optional<Vec2> mouse;            ///< [Pixels] cursor, when known
    bool leftDown = false;                ///< the left button is down at the end of the frame
    bool leftPressed = false, leftReleased = false; ///< it went down / up during the frame
    double lookDx = 0;                    ///< [Pixels] mouse-look motion
    double wheel = 0;                     ///< [Notches]
    bool quit = false;

    bool isDown(Key k) const { return down[std::size_t(k)]; }
    bool wasPressed(Key k) const;
    /// Adds `other` to this frame (window and script together): keys and buttons or-ed, motion summed,
    /// other's cursor wins when it has one.
    void merge(const InputFrame& other);
};

/// A parsed script, played frame by frame.
class InputScript {
public:
    /// @throws InvalidInput("<file>:<line>", what) on the first bad line; and when the file cannot be read.
    static InputScript load(const std::string& path);
    /// As load, from text; `name` is the file name in errors.
    static InputScript parse(const std::string& text, const std::string& name);

    /// The input of frame `frame`; frames must be asked for in order 0, 1, 2, ... (holds and the button
    /// carry over).
    InputFrame next(std::size_t frame);
    /// The last frame any event names (0 for an empty script).
    std::size_t lastFrame() const { return m_lastFrame; }

private:
    enum class Kind { Key, Hold, Mouse, Click, Press, Release, Look, Wheel, Quit };
    struct Event {
        std::size_t frame = 0;
        Kind kind = Kind::Key;
        Key key = Key::A;
        long count = 0;
        Vec2 at{0.0};
    };
    std::vector<Event> m_events; // sorted by frame, stable
    std::size_t m_cursor = 0, m_lastFrame = 0;
    std::array<std::size_t, kKeyCount> m_holdUntil{}; // key held while frame < m_holdUntil
    bool m_leftDown = false;
    std::optional<Vec2> m_mouse;
};

} // namespace rgvc::sim
