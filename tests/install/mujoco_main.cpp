// Downstream consumer of an installed coopdyn's MuJoCo adapter: the header, MuJoCo's headers and
// its library must all come through find_package(coopdyn CONFIG COMPONENTS mujoco) and
// coopdyn::mujoco alone.
#include <coopdyn/adapters/mujoco.hpp>

#include <cstdio>

int main()
{
    std::printf("MuJoCo %d\n", mj_version());  // links MuJoCo
    try {
        const coopdyn::MujocoArms<> arms(nullptr, {"a"}, {"b"});  // refused: no model
    } catch (const coopdyn::InvalidModel& error) {
        return error.parameter() == "model" ? 0 : 1;
    }
    return 1;
}
