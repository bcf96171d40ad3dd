/* hfi-sensorless plant: the public C API.
 *
 * This file is the single source of the plant's data layout. It is included by plant.c and parsed by
 * cffi (golden/plant/binding.py), so it holds declarations only: no preprocessor lines, no
 * initialisers. Units are SI (V, A, Wb, H, ohm, s, N*m, kg*m^2, rad); time is counted in integer ticks
 * of the FPGA clock (tick_hz, 100 MHz by default).
 *
 * Frames (docs/plant.md): amplitude-invariant Clarke transform; rotor frame d = magnet axis (or, on a
 * machine without magnet, the axis of LOWER inductance), q leads d by 90 deg electrical;
 * x_d = cos(th) x_a + sin(th) x_b, x_q = -sin(th) x_a + cos(th) x_b; th = p * theta_m.
 */

/* ---- magnetic model: stator currents as a function of rotor-frame flux linkages ---------------- */
enum mag_kind {
    MAG_LINEAR = 0,    /* i_d = (psi_d - psi_f)/L_d, i_q = psi_q/L_q                                */
    MAG_DSAT = 1,      /* linear q; d saturates: i_d = h(psi_d) - h(psi_f),                          *
                        * h(x) = x/L_d0 * (1 + dsat_a*|x/psi_f|^dsat_S), L_d = incremental at i=0   */
    MAG_ALGEBRAIC = 2, /* algebraic saturation with cross-saturation (Hinkkanen et al. 2017 form),   *
                        * x = psi_d - psi_f, y = psi_q:                                             *
                        * i_d = (a_d0 + a_dd|x|^S + a_dq/(V+2)|x|^U |y|^(V+2)) x                     *
                        * i_q = (a_q0 + a_qq|y|^T + a_dq/(U+2)|x|^(U+2) |y|^V) y                     */
    MAG_TABLE = 3      /* i_d, i_q tabulated on a regular (psi_d, psi_q) grid, bilinear             */
};

struct mag_params {
    int kind;              /* enum mag_kind */
    double psi_f;          /* magnet flux linkage on d [Wb] (>= 0) */
    double L_d, L_q;       /* MAG_LINEAR; MAG_DSAT: L_d incremental at i = 0, L_q constant [H] */
    double dsat_a;         /* MAG_DSAT: saturation coefficient (0 = linear) */
    int dsat_S;            /* MAG_DSAT: saturation exponent (even, >= 2) */
    double a_d0, a_dd, a_q0, a_qq, a_dq; /* MAG_ALGEBRAIC coefficients [A/Wb^(1+n)] */
    int S, T, U, V;        /* MAG_ALGEBRAIC exponents (integers >= 0) */
    int tab_nd, tab_nq;    /* MAG_TABLE: grid size (>= 2 each) */
    double tab_psid0, tab_dpsid, tab_psiq0, tab_dpsiq; /* grid origin and spacing [Wb] */
    const double *tab_id;  /* [tab_nq][tab_nd], row-major: tab_id[iq*tab_nd + id] */
    const double *tab_iq;
};

/* ---- mechanics and piecewise-linear profiles --------------------------------------------------- */
struct profile {           /* value(t): linear between points, held before the first / after the last */
    int n;                 /* number of points (0 = value 0) */
    const double *t;       /* [n] non-decreasing times [s]; two equal times make a step */
    const double *v;       /* [n] values */
    double puls_freq;      /* multiplied by (1 + puls_depth*sin(2*pi*puls_freq*t)) [Hz] */
    double puls_depth;     /* relative depth (0 = none) */
};

struct mech_params {
    int pole_pairs;
    double J;              /* inertia of motor + coupled load [kg*m^2] */
    double B;              /* viscous friction [N*m*s/rad] */
    double T_c;            /* Coulomb friction [N*m] */
    double w_stick;        /* Coulomb friction is T_c*sat(w/w_stick) [rad/s mech] */
    int imposed_speed;     /* 1: speed profile (rad/s mech) imposed by the load machine */
};

/* ---- inverter ------------------------------------------------------------------------------------ */
struct inverter_params {
    double V_dc;           /* nominal dc-link voltage [V] */
    double R_dc;           /* dc source resistance: V = V_dc - R_dc*i_dc (sag) [ohm] */
    double ripple_amp;     /* dc-link ripple amplitude [V] */
    double ripple_freq;    /* dc-link ripple frequency [Hz] */
    double v_sw, r_sw;     /* conducting switch drop v_sw + r_sw*|i| [V, ohm] */
    double v_diode, r_diode; /* conducting diode drop [V, ohm] */
    double C_node;         /* phase-node capacitance charged by the phase current during dead time [F]; *
                            * 0 = ideal diode commutation at the instant of turn-off                   */
};

/* ---- current sensors and ADC -------------------------------------------------------------------- */
struct sensor_params {
    double gain[3];        /* per phase gain (1 = ideal) */
    double offset[3];      /* per phase offset [A] */
    double noise_rms;      /* white Gaussian noise per sample [A rms] */
    double bandwidth_hz;   /* first-order sensor bandwidth (0 = infinite) [Hz] */
    double ring_amp;       /* ringing amplitude on the switched phase after a switch turns on [A] */
    double ring_freq;      /* ringing frequency [Hz] */
    double ring_tau;       /* ringing decay time constant [s] */
    double ring_cross;     /* ringing on the two other phases, relative to ring_amp */
    int adc_bits;          /* ADC resolution (1..24) */
    double adc_range;      /* +-adc_range [A] spans codes 0 .. 2^adc_bits-1; mid-scale = 0 A */
    /* the dc-link voltage channel (ADC channel 3, same resolution, sampled with the currents): the link *
     * voltage through a divider of gain vdc_gain, plus white noise of its own random stream, so that    *
     * the current channels' samples do not depend on it; 0 .. vdc_range [V] spans codes 0 .. 2^adc_bits-1 */
    double vdc_range;      /* full scale [V]; 0 = no channel (code 0) */
    double vdc_gain;       /* divider gain error (1 = ideal) */
    double vdc_noise_rms;  /* white Gaussian noise per sample [V rms] */
};

/* ADC channels per sample: the phase currents a, b, c (codes of sens.adc_range), then the dc link */
#define PLANT_ADC_CHANNELS 4
#define PLANT_ADC_VDC 3

/* ---- faults (docs/faults.md): each acts from its tick on, until its end tick or the end of the run -- */
enum fault_kind {
    FAULT_SENSOR_OFFSET = 1, /* sensor channel: offset += value [A] + rate*(t - t_fault) [A/s]         */
    FAULT_SENSOR_GAIN = 2,   /* sensor channel: gain *= value                                          */
    FAULT_ADC_STUCK = 3,     /* ADC channel (0..3, 3 = the dc link) reads code (int)value whatever it measures */
    FAULT_PHASE_OPEN = 4,    /* phase `channel` disconnected between inverter and motor: i_k = 0       */
    FAULT_SWITCH_OPEN = 5,   /* switch `channel` (gate mask bit 0..5) never turns on                   */
    FAULT_DC_LINK = 6,       /* dc-link source: V_dc * (value + (1 - value)*exp(-(t - t_fault)/rate)),  *
                              * value 0..2, rate = time constant [s] (0: a step)                        */
    FAULT_LOAD_STEP = 7,     /* load torque += value [N*m] (negative: the load drives the motor)        */
    FAULT_ROTOR_BLOCKED = 8  /* the rotor is held at its angle: speed 0 from the fault on              */
};

struct fault {
    int kind;              /* enum fault_kind */
    int channel;           /* phase 0..2, ADC channel 0..3 (FAULT_ADC_STUCK), or switch 0..5 (FAULT_SWITCH_OPEN); else 0 */
    long long tick;        /* onset [ticks]; faults are listed in non-decreasing tick order */
    long long until;       /* the fault clears at this tick (0: never; else > tick) */
    double value;          /* see enum fault_kind */
    double rate;           /* see enum fault_kind */
};

struct plant_params {
    double tick_hz;        /* FPGA clock [Hz] */
    int max_substep_ticks; /* longest RK4 step [ticks] */
    int max_substep_commutation_ticks; /* longest step while a leg commutates through C_node [ticks] */
    unsigned long long seed;
    double R_s;            /* stator resistance [ohm] */
    struct mag_params mag;
    struct mech_params mech;
    struct inverter_params inv;
    struct sensor_params sens;
    struct profile load;   /* load torque [N*m], opposes positive speed when positive */
    struct profile speed;  /* imposed mechanical speed [rad/s] when mech.imposed_speed */
    double theta_m0;       /* initial mechanical angle [rad] */
    double omega_m0;       /* initial mechanical speed [rad/s] */
    int n_faults;          /* number of entries of faults (0: none) */
    const struct fault *faults;
};

/* ---- true state, for metrics --------------------------------------------------------------------- */
struct plant_state {
    long long tick;
    double t;              /* [s] */
    double theta_e;        /* electrical angle, wrapped to [0, 2*pi) */
    double omega_e;        /* electrical speed [rad/s] */
    double theta_m, omega_m;
    double psi_d, psi_q, i_d, i_q;
    double i_abc[3];
    double v_node[3];      /* phase-node voltages w.r.t. the negative dc rail [V] */
    double v_d, v_q;       /* machine terminal voltages, rotor frame [V] */
    double v_dc;           /* instantaneous dc-link voltage [V] */
    double torque;         /* electromagnetic torque [N*m] */
    double load_torque;    /* [N*m] */
    double sensor_y[3];    /* sensor outputs before gain/offset/noise/ringing [A] */
    double E_in;           /* integral of 1.5*(v_d i_d + v_q i_q) [J] */
    double E_cu;           /* integral of 1.5*R_s*(i_d^2 + i_q^2) [J] */
    double E_mech;         /* integral of torque*omega_m [J] */
    double Q_d, Q_q;       /* integrals of i_d and i_q [A*s]: window means of the current, exact */
    double T_int, T2_int;  /* integrals of torque [N*m*s] and torque^2 [N^2*m^2*s]: its ripple inside a window */
    int gates;             /* current gate mask (bit 2k: leg k high switch, bit 2k+1: low switch) */
    int voltage_mode;      /* 1 while driven by ideal voltages instead of gates */
    long long shoot_through_ticks; /* ticks with both switches of a leg on (hardware fault) */
};

/* ---- API ------------------------------------------------------------------------------------------- */
struct plant;

/* Returns NULL and writes a message into err (err_len bytes) when a parameter is invalid. */
struct plant *plant_create(const struct plant_params *params, char *err, int err_len);
void plant_free(struct plant *p);

/* Per-event API. Ticks must not go backwards (returns PLANT_BAD_ORDER). */
int plant_set_gates(struct plant *p, int gates);
int plant_set_voltage(struct plant *p, const double v_abc[3]); /* ideal voltages, zero sequence ignored */
int plant_advance(struct plant *p, long long tick);
/* Samples the PLANT_ADC_CHANNELS channels at the current tick: adc codes and the analog values
 * ([A] for the currents, [V] for the dc link). Returns 0, or PLANT_NOT_FINITE when a sensed value is NaN or
 * infinite (the state diverged: motor or inverter values far outside any real machine; the codes are then
 * undefined). */
/* The statuses of the calls below (0 is success); plant_status_text gives each one's message, the one wording
 * every binding (golden/plant/binding.py, sim/plant_loop.cpp) reports. */
enum {
    PLANT_BAD_ORDER = -1,     /* a tick before the plant's time, or edge/sample ticks out of order */
    PLANT_SHOOT_THROUGH = -2, /* a gate mask turned on both switches of a leg (the plant runs on) */
    PLANT_BAD_MASK = -3,      /* a gate mask outside 0..63 */
    PLANT_NOT_FINITE = -4     /* a sensed value is NaN or infinite: the state diverged */
};
const char *plant_status_text(int status);
int plant_sample(struct plant *p, int adc[PLANT_ADC_CHANNELS], double analog[PLANT_ADC_CHANNELS]);
void plant_get_state(const struct plant *p, struct plant_state *out);

/* Snapshots (the golden loop's hardware overcurrent trip re-runs a window from its start with the gates cut):
 * plant_save copies everything that changes while the plant runs (its time, state, random streams, memos, fault
 * effects) into buf (plant_snapshot_size() bytes); plant_restore puts the plant back into that moment. A snapshot
 * belongs to the plant it was taken of: restoring it into another returns -1 and changes nothing. */
size_t plant_snapshot_size(void);
void plant_save(const struct plant *p, void *buf);
int plant_restore(struct plant *p, const void *buf);

/* Batch API: applies gate edges (or ideal voltage steps, when volts != NULL; then gates may be NULL)
 * and takes samples, merged by tick; at equal ticks, the input change comes before the sample.
 * adc_out: [n_samples*PLANT_ADC_CHANNELS]; analog_out (same layout) and truth_out may be NULL. Returns 0; PLANT_BAD_ORDER on a bad tick order
 * (events up to it are applied); PLANT_SHOOT_THROUGH when a gate mask turned on both switches of a leg (the run
 * goes on); PLANT_BAD_MASK when a gate mask is outside 0..63 (checked first: nothing is applied); PLANT_NOT_FINITE
 * when a sample's value is not finite (the run stops there). */
int plant_run(struct plant *p,
              int n_edges, const long long *edge_ticks, const int *gates, const double *volts,
              int n_samples, const long long *sample_ticks,
              int *adc_out, double *analog_out, struct plant_state *truth_out);

/* Magnetic model (for tests and tools): out = [i_d, i_q, di_d/dpsi_d, di_d/dpsi_q, di_q/dpsi_d,
 * di_q/dpsi_q] at the given flux linkages. */
void plant_mag_eval(const struct mag_params *m, double psi_d, double psi_q, double out[6]);
