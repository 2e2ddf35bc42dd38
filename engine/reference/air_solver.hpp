// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The offline reference of sound in air around a thin screen (issue 19, "The umbrella in air"): a 3-D
// finite-difference time-domain solver of linear acoustics, independent of the server's models, with a
// structure (a piston, a rigid disc, a membrane) coupled to the air on both of its faces. docs/air-reference.md
// has the method, its equations, the boundary's measured reflection and the validation figures.
//
// Interface:
//   GridSpec g = GridSpec::box(dx, half_x, half_y, z_below, z_above);   // interior extents (m) around the
//                                  // screen plane z = 0, plus g.pml_cells of absorbing layer on each side
//   ScreenStructure s;             // DOFs: mass, springs, damping, prescribed flags
//   s.add_dof(mass_kg) ... s.add_spring(a, b, k) (b = -1: to a fixed anchor)
//   AirSolver air(g, s);           // allocates; throws std::invalid_argument on a bad grid
//   air.set_face(i, j, AirSolver::rigid) / air.set_face(i, j, dof)   // the screen plane's faces (default air)
//   air.face_x(i), air.face_y(j)   // the plan position (m) of screen face (i, j)
//   air.set_external_force(dof, N) // held until changed; applied at every step
//   air.prescribe_velocity(dof, v) // a prescribed DOF's velocity over the coming step (t_n .. t_n+1)
//   air.step()                     // one time step (no allocation after the first)
//   air.add_pressure(i, j, k, pa)  // a point source: added to one cell outside the layers
//   air.pressure_at(x, y, z)       // Pa, trilinear between cell centres, at the current time t_n
//   air.dof_velocity(d), air.dof_displacement(d), air.dof_air_force(d)   // the last step's
//   air.set_air_loading(false)     // the structure in vacuum: the air neither drives nor is driven
//   int q = air.add_probe(x, y, z) // a pressure time series, one sample per step after it (at t_n+1):
//   air.probe(q)                   //   air.probe(q)[n]; add_dof_probe(d): dof_probe_velocity(q) and
//                                  //   dof_probe_force(q) (the air's force), likewise; reserve_probes(steps)
//                                  //   keeps step() from allocating
// A point within half a cell of the screen interpolates across it: listen at |z| >= dx / 2.
//
// The grid (Yee 1966; for acoustics Botteldooren 1994): pressure at cell centres, each particle-velocity
// component on the faces normal to it; leapfrog in time, velocity at half steps. rho0 and c are
// constants::air_density and constants::speed_of_sound_air unless set in the GridSpec. Coordinates:
// x, y from the box's centre line (nx, ny even, so x = 0 is a face line), z from the screen plane,
// which is the plane of z-faces k = screen_k. Box walls behind the absorbing layers are rigid.
// Absorbing layers: Berenger's split-field PML (pressure split into px + py + pz inside the layers only),
// quadratic grading, exponential time differencing.
// The screen: each of its faces is air (the ordinary update), rigid (v = 0) or owned by one DOF of the
// structure, whose velocity it takes; the DOF's force gets -(p_above - p_below) dx^2 from each of its
// faces (the transpose of the coupling, so the coupled scheme conserves energy).
// Structure stepping: symplectic Euler at the air's time step (velocity at half steps, like the air's),
// with sub-steps when the structure's own Gershgorin bound (omega_max dt < 1.9) asks for them; the air
// force is held over the sub-steps and the faces take the mean velocity over the step.
// Precision: the air in float (bandwidth and SIMD width; its rounding, ~1e-7 of the field, is 100 dB
// under the validations' tolerances), the structure in double.

#include <array>
#include <cstddef>
#include <vector>

namespace ameoto::reference {

struct GridSpec {
    int nx = 0, ny = 0, nz = 0;     // cells, absorbing layers included; nx, ny even
    int screen_k = -1;              // the screen's plane of z-faces (1 .. nz-1); -1: no screen
    double dx = 0.01;               // m
    double courant = 0.5;           // c dt / dx, below 1 / sqrt(3)
    int pml_cells = 10;             // thickness of each absorbing layer
    double pml_reflection = 1e-4;   // design reflection of the layer at normal incidence (continuum)
    std::array<bool, 3> pml_low{true, true, true}, pml_high{true, true, true};   // per side; false: rigid wall
    double density = 0.0;           // kg/m^3; 0: constants::air_density
    double sound_speed = 0.0;       // m/s; 0: constants::speed_of_sound_air

    // A box around the screen plane z = 0: interior |x| <= half_x, |y| <= half_y, -z_below <= z <= z_above
    // (rounded up to whole cells), absorbing layers outside it.
    // layer_below = false: a rigid floor at z = -z_below instead of an absorbing layer (a baffle's back).
    static GridSpec box(double dx, double half_x, double half_y, double z_below, double z_above, int pml_cells = 10,
                        bool layer_below = true);
    double time_step() const;
};

struct Spring {
    int a = 0, b = -1;              // DOFs; b = -1: a fixed anchor
    double stiffness = 0.0;         // N/m
};

struct ScreenStructure {
    std::vector<double> mass;       // kg per DOF
    std::vector<char> prescribed;   // 1: the DOF's velocity is given (prescribe_velocity), not integrated
    std::vector<Spring> springs;
    double mass_damping = 0.0;      // alpha, 1/s (force -alpha m v)
    double stiffness_damping = 0.0; // beta, s (force -beta K v)
    std::vector<double> initial_displacement;   // m per DOF (empty: at rest)

    int add_dof(double mass_kg, bool is_prescribed = false);
    void add_spring(int a, int b, double stiffness) { springs.push_back({a, b, stiffness}); }
    int size() const { return static_cast<int>(mass.size()); }
};

// Steps a ScreenStructure by itself (symplectic Euler); AirSolver uses it, and it is the vacuum reference.
class StructureStepper {
public:
    StructureStepper(const ScreenStructure& s, double time_step_s);
    // One step of dt with the given extra force per DOF (air plus external; held over the sub-steps).
    void step(const double* force);
    void set_prescribed_velocity(int dof, double v) { velocity_[static_cast<std::size_t>(dof)] = v; }
    double velocity(int dof) const { return mean_velocity_[static_cast<std::size_t>(dof)]; }   // over the last step
    double displacement(int dof) const { return x_[static_cast<std::size_t>(dof)]; }
    int sub_steps() const { return sub_steps_; }
    int size() const { return static_cast<int>(mass_.size()); }

private:
    std::vector<double> mass_, inverse_mass_, x_, velocity_, mean_velocity_, spring_force_, x_start_;
    std::vector<char> prescribed_;
    std::vector<Spring> springs_;
    double alpha_ = 0.0, beta_ = 0.0, dt_ = 0.0;
    int sub_steps_ = 1;
};

class AirSolver {
public:
    static constexpr int air = -1;
    static constexpr int rigid = -2;

    AirSolver(const GridSpec& grid, const ScreenStructure& structure = ScreenStructure{});

    const GridSpec& grid() const { return grid_; }
    double time_step() const { return dt_; }
    double time() const { return static_cast<double>(steps_) * dt_; }
    long steps() const { return steps_; }
    double density() const { return rho_; }
    double sound_speed() const { return c_; }

    void set_face(int i, int j, int owner);        // air, rigid, or a DOF index
    int face(int i, int j) const { return owner_[static_cast<std::size_t>(j * grid_.nx + i)]; }
    double face_x(int i) const { return (i + 0.5 - grid_.nx / 2) * grid_.dx; }   // plan centre of face (i, j)
    double face_y(int j) const { return (j + 0.5 - grid_.ny / 2) * grid_.dx; }
    int faces_of(int dof) const;                   // how many screen faces the DOF owns

    void set_external_force(int dof, double newtons) { external_[static_cast<std::size_t>(dof)] = newtons; }
    void prescribe_velocity(int dof, double v) { structure_.set_prescribed_velocity(dof, v); }
    void set_air_loading(bool on) { air_loading_ = on; }

    void step();
    void add_pressure(int i, int j, int k, double pa);   // a monopole source: pa added to one interior cell

    double pressure_at(double x, double y, double z) const;   // trilinear between cell centres
    double cell_pressure(int i, int j, int k) const { return p_[index(i, j, k)]; }
    double dof_velocity(int dof) const { return structure_.velocity(dof); }
    double dof_displacement(int dof) const { return structure_.displacement(dof); }
    double dof_air_force(int dof) const { return air_force_[static_cast<std::size_t>(dof)]; }
    const StructureStepper& structure() const { return structure_; }
    double acoustic_energy() const;                // J in the interior (not the layers)

    int add_probe(double x, double y, double z);
    const std::vector<double>& probe(int q) const { return probes_[static_cast<std::size_t>(q)].samples; }
    int add_dof_probe(int dof);
    const std::vector<double>& dof_probe_velocity(int q) const { return dof_probes_[static_cast<std::size_t>(q)].velocity; }
    const std::vector<double>& dof_probe_force(int q) const { return dof_probes_[static_cast<std::size_t>(q)].force; }
    void reserve_probes(std::size_t steps);
    std::size_t cells() const { return p_.size(); }

private:
    std::size_t index(int i, int j, int k) const {
        return (static_cast<std::size_t>(k) * static_cast<std::size_t>(grid_.ny) + static_cast<std::size_t>(j)) *
                   static_cast<std::size_t>(grid_.nx) + static_cast<std::size_t>(i);
    }
    void update_velocity();
    void update_pressure();
    void couple_screen();

    GridSpec grid_;
    double dt_ = 0.0, rho_ = 0.0, c_ = 0.0;
    long steps_ = 0;
    bool air_loading_ = true;
    // Fields: p total everywhere, px/py/pz meaningful in the absorbing cells only; each velocity array is
    // padded by one plane of zero faces so that the high walls read as v = 0.
    std::vector<float> p_, px_, py_, pz_, vx_, vy_, vz_;
    // Per axis: cell coefficients (a, b) of the pressure update and face coefficients of the velocity update.
    std::array<std::vector<float>, 3> cell_a_, cell_b_, face_a_, face_b_;
    std::array<std::vector<char>, 3> absorbing_;   // per axis, per cell: inside a layer
    int inner_lo_ = 0, inner_hi_ = 0;              // x cells [lo, hi) outside the x layers
    std::vector<int> owner_;                       // per screen face (j * nx + i)
    std::vector<int> owned_faces_;                 // face indices that a DOF owns, grouped by DOF
    std::vector<int> owned_start_;                 // owned_faces_ of DOF d: [start[d], start[d+1])
    std::vector<int> rigid_faces_;
    bool faces_dirty_ = true;
    StructureStepper structure_;
    std::vector<double> external_, air_force_, total_force_;
    struct Probe {
        double x, y, z;
        std::vector<double> samples;
    };
    struct DofProbe {
        int dof;
        std::vector<double> velocity, force;
    };
    std::vector<Probe> probes_;
    std::vector<DofProbe> dof_probes_;
};

}  // namespace ameoto::reference
