// rgvc_sim2d: the 2D top-view simulator (README, "2D simulator"). Usage: SimCli.cpp's kUsage.
#include "SimCli.hpp"

#include "rgvc/grid/Error.hpp"
#include "rgvc/render/gl/GlError.hpp"

#include <iostream>

namespace {

std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

} // namespace

int main(int argc, char** argv) {
    using namespace rgvc::sim;
    try {
        const SimOptions options = parseSimOptions(argc, argv);
        if (options.help) {
            std::cout << kUsage;
            return 0;
        }
        return runSim(options);
    } catch (const UsageError& e) {
        std::cerr << "rgvc_sim2d: " << oneLine(e.what()) << "\n";
    } catch (const rgvc::SceneError& e) {
        std::cerr << "rgvc_sim2d: " << oneLine(e.what()) << "\n";
    } catch (const rgvc::InvalidInput& e) {
        std::cerr << "rgvc_sim2d: " << oneLine(e.what()) << "\n";
    } catch (const rgvc::GlError& e) {
        std::cerr << "rgvc_sim2d: " << oneLine(e.what()) << "\n";
    } catch (const std::runtime_error& e) { // a PNG that cannot be written
        std::cerr << "rgvc_sim2d: " << oneLine(e.what()) << "\n";
    }
    return 2;
}
