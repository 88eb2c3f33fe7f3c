"""Index layout of the flat parameter and state arrays the kernels read.

The parameter array ``params`` (float64, length ``N_PARAMS``, plus a tail for an
implicit polynomial shape, see below) is built once by
``celtstone.models`` from validated objects; the state array ``y`` (float64,
length ``N_STATE``) is shared by both models so one integrator serves both.

State (all in body axes unless said otherwise)
----------------------------------------------
``y[0:3]``    n, upward vertical unit vector [1]
``y[3:6]``    omega, angular velocity [rad/s]
``y[6:9]``    V1, sliding velocity of the contact point [m/s] (zero in rolling)
``y[9:13]``   attitude quaternion (w, x, y, z), body -> space [1]
``y[13:15]``  horizontal position of the centre of mass in space axes [m]
``y[15]``     work dissipated by friction and damping since t = 0 [J]
"""

from __future__ import annotations

# model codes
MODEL_ROLLING = 0
MODEL_SLIDING = 1
MODEL_STICK = 2  # hybrid contact, stick phase: no slip, no pivoting (kernels/stick.py)

# shape codes
SHAPE_ELLIPSOID = 0
SHAPE_PARABOLOID = 1
SHAPE_SUPERELLIPSOID = 2  # |x/a|^p + |y/b|^p + |z/c|^p = 1
SHAPE_IMPLICIT = 3  # F(x) = sum_k c_k x^i_k y^j_k z^l_k = 1, terms in the tail below

# normal-force options of the sliding model
NORMAL_FORCE_STATIC = 0
NORMAL_FORCE_DYNAMIC = 1

# friction laws and contact-pressure distributions of the sliding model
FRICTION_PADE = 0  # Zhuravlev's Padé approximation, paper eq. (10)
FRICTION_EXACT = 1  # the Coulomb–Contensou integrals of paper section 2
PRESSURE_HERTZ = 0  # sigma ∝ sqrt(eps² − r²), paper eq. (2)
PRESSURE_UNIFORM = 1  # sigma = N / (pi eps²)

# parameter indices
P_MASS = 0  # m [kg]
P_GRAVITY = 1  # g [m/s^2]
P_INERTIA = 2  # central inertia tensor, row-major 3x3, P_INERTIA .. P_INERTIA + 8 [kg m^2]
P_SHAPE = 11  # shape code
P_SHAPE_0 = 12  # ellipsoid: semi-axis a [m];  paraboloid: rho1 [m]
P_SHAPE_1 = 13  # ellipsoid: semi-axis b [m];  paraboloid: rho2 [m]
P_SHAPE_2 = 14  # ellipsoid: semi-axis c [m];  paraboloid: l, height of G above the contact [m]
P_SHAPE_3 = 15  # ellipsoid: h, G below the centre [m]; paraboloid: unused
# (a superellipsoid reads P_SHAPE_0 .. P_SHAPE_3 as the ellipsoid, plus P_SHAPE_4;
#  an implicit polynomial reads P_SHAPE_0 .. P_SHAPE_2 as the semi-axes of its start
#  ellipsoid, P_SHAPE_3 as h and P_SHAPE_4 as the number of terms, see the tail below)
P_DAMPING = 16  # sigma, viscous torque coefficient [N m s]
P_FRICTION = 17  # f, friction coefficient [1]
P_CONTACT_RADIUS = 18  # epsilon, Hertz contact radius [m]
P_NORMAL_FORCE = 19  # normal-force option code
P_REGULARISATION = 20  # delta, slip-speed regularisation scale [m/s]
P_FRICTION_LAW = 21  # friction-law code FRICTION_*
P_CONTACT_PRESSURE = 22  # contact-pressure code PRESSURE_*
P_CONTACT_MODULUS = 23  # E*, effective modulus of the Hertz contact [Pa]; 0: fixed epsilon
P_SHAPE_4 = 24  # superellipsoid: exponent p [1], >= 2; implicit: number of terms; else unused
N_PARAMS = 25

# Variable tail, present only for SHAPE_IMPLICIT (params then has length
# N_PARAMS + 3 + 4 * number of terms; docs/decisions.md section 17):
P_IMPLICIT_CENTRE = N_PARAMS  # centre of the start ellipsoid, 3 numbers, about O [m]
P_IMPLICIT_TERMS = N_PARAMS + 3  # 4 numbers per term: c [m^-(i+j+l)], i, j, l

# state indices
Y_N = 0
Y_OMEGA = 3
Y_SLIP = 6
Y_QUAT = 9
Y_POSITION = 13
Y_WORK = 15
N_STATE = 16

# status codes returned by the right-hand side
RHS_OK = 0
RHS_SINGULAR = 1  # the linear system for the angular acceleration is singular
RHS_OFF_SHAPE = 2  # the contact point left the shape's domain (paraboloid n3 <= 0)
RHS_NON_CONVEX = 3  # implicit shape: no contact point found, or the surface is not convex there
