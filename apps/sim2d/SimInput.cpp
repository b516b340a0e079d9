#include "SimInput.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace rgvc::sim {

namespace {

const char* const kNamedKeys[] = {"space", "tab", "escape", "left", "right", "up", "down"};

} // namespace

std::string keyName(Key k) {
    const int i = int(k);
    if (i < 26) return std::string(1, char('a' + i));
    if (i < 36) return std::string(1, char('0' + i - 26));
    if (i < kKeyCount) return kNamedKeys[i - 36];
    return "?";
}

std::optional<Key> parseKey(const std::string& name) {
    for (int i = 0; i < kKeyCount; ++i)
        if (keyName(Key(i)) == name) return Key(i);
    return std::nullopt;
}

bool InputFrame::wasPressed(Key k) const { return std::find(pressed.begin(), pressed.end(), k) != pressed.end(); }

void InputFrame::merge(const InputFrame& o) {
    for (int i = 0; i < kKeyCount; ++i) down[std::size_t(i)] = down[std::size_t(i)] || o.down[std::size_t(i)];
    pressed.insert(pressed.end(), o.pressed.begin(), o.pressed.end());
    if (o.mouse) mouse = o.mouse;
    leftDown = leftDown || o.leftDown;
    leftPressed = leftPressed || o.leftPressed;
    leftReleased = leftReleased || o.leftReleased;
    lookDx += o.lookDx;
    wheel += o.wheel;
    quit = quit || o.quit;
}

InputScript InputScript::load(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InvalidInput(path, "cannot read the script file");
    std::ostringstream text;
    text << in.rdbuf();
    return parse(text.str(), path);
}

InputScript InputScript::parse(const std::string& text, const std::string& name) {
    InputScript s;
    std::istringstream lines(text);
    std::string line;
    for (std::size_t lineNo = 1; std::getline(lines, line); ++lineNo) {
        if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string t; words >> t;) w.push_back(t);
        if (w.empty()) continue;
        const std::string where = name + ":" + std::to_string(lineNo);
        auto integer = [&](const std::string& t, long lo, long hi, const char* what) {
            std::size_t used = 0;
            long v = 0;
            try {
                v = std::stol(t, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != t.size() || v < lo || v > hi)
                throw InvalidInput(where, std::string(what) + " must be an integer in [" + std::to_string(lo) + ", " +
                                              std::to_string(hi) + "], got '" + t + "'");
            return v;
        };
        auto number = [&](const std::string& t, const char* what) {
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(t, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != t.size() || !std::isfinite(v) || std::abs(v) > 1e6)
                throw InvalidInput(where, std::string(what) + " must be a finite number within 1e6, got '" + t + "'");
            return v;
        };
        auto arity = [&](std::size_t n, const char* usage) {
            if (w.size() != n) throw InvalidInput(where, std::string("expected '") + usage + "'");
        };
        Event e;
        e.frame = std::size_t(integer(w[0], 0, 100000000, "the frame"));
        if (w.size() < 2) throw InvalidInput(where, "expected 'FRAME EVENT ...'");
        const std::string& ev = w[1];
        auto key = [&](const std::string& t) {
            const std::optional<Key> k = parseKey(t);
            if (!k) throw InvalidInput(where, "unknown key '" + t + "' (a-z, 0-9, space, tab, escape, left, right, up, down)");
            return *k;
        };
        if (ev == "key") {
            arity(3, "FRAME key NAME");
            e.kind = Kind::Key;
            e.key = key(w[2]);
        } else if (ev == "hold") {
            arity(4, "FRAME hold NAME FRAMES");
            e.kind = Kind::Hold;
            e.key = key(w[2]);
            e.count = integer(w[3], 1, 100000000, "the hold's length");
        } else if (ev == "mouse" || ev == "click" || ev == "press" || ev == "release") {
            arity(4, ("FRAME " + ev + " X Y").c_str());
            e.kind = ev == "mouse" ? Kind::Mouse : ev == "click" ? Kind::Click : ev == "press" ? Kind::Press : Kind::Release;
            e.at = {number(w[2], "X"), number(w[3], "Y")};
        } else if (ev == "look") {
            arity(3, "FRAME look DX");
            e.kind = Kind::Look;
            e.at.x = number(w[2], "DX");
        } else if (ev == "wheel") {
            arity(3, "FRAME wheel DY");
            e.kind = Kind::Wheel;
            e.at.y = number(w[2], "DY");
        } else if (ev == "quit") {
            arity(2, "FRAME quit");
            e.kind = Kind::Quit;
        } else {
            throw InvalidInput(where, "unknown event '" + ev + "' (key, hold, mouse, click, press, release, look, wheel, quit)");
        }
        s.m_lastFrame = std::max(s.m_lastFrame, e.frame);
        s.m_events.push_back(e);
    }
    std::stable_sort(s.m_events.begin(), s.m_events.end(), [](const Event& a, const Event& b) { return a.frame < b.frame; });
    return s;
}

InputFrame InputScript::next(std::size_t frame) {
    InputFrame f;
    while (m_cursor < m_events.size() && m_events[m_cursor].frame < frame) ++m_cursor; // frames skipped
    bool upAfter = false; // a click: down during the frame, up at its end
    for (; m_cursor < m_events.size() && m_events[m_cursor].frame == frame; ++m_cursor) {
        const Event& e = m_events[m_cursor];
        const std::size_t k = std::size_t(e.key);
        switch (e.kind) {
        case Kind::Key: f.pressed.push_back(e.key); break;
        case Kind::Hold:
            f.pressed.push_back(e.key);
            m_holdUntil[k] = std::max(m_holdUntil[k], frame + std::size_t(e.count));
            break;
        case Kind::Mouse: m_mouse = e.at; break;
        case Kind::Click:
            m_mouse = e.at;
            f.leftPressed = true;
            upAfter = true;
            break;
        case Kind::Press:
            m_mouse = e.at;
            f.leftPressed = !m_leftDown;
            m_leftDown = true;
            break;
        case Kind::Release:
            m_mouse = e.at;
            f.leftReleased = m_leftDown;
            m_leftDown = false;
            break;
        case Kind::Look: f.lookDx += e.at.x; break;
        case Kind::Wheel: f.wheel += e.at.y; break;
        case Kind::Quit: f.quit = true; break;
        }
    }
    for (int i = 0; i < kKeyCount; ++i) f.down[std::size_t(i)] = frame < m_holdUntil[std::size_t(i)];
    f.mouse = m_mouse;
    f.leftDown = m_leftDown || (upAfter && !f.leftReleased);
    if (upAfter) {
        f.leftReleased = true;
        f.leftDown = m_leftDown;
    }
    return f;
}

} // namespace rgvc::sim
