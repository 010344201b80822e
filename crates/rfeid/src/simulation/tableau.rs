//! Explicit Runge–Kutta methods, as Butcher tableaux.
//!
//! The simulator takes a fixed number of equal steps per sample interval, so
//! the discretisation is the same for every parameter point: the computed
//! response is a smooth function of the parameters, and its derivative is
//! what the sensitivities return (see [`super::run`]).

// Coefficients are quoted with the digits they were published with.
#![allow(clippy::excessive_precision)]

/// An explicit Runge–Kutta method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau {
    /// Name for reports.
    pub name: &'static str,
    /// Classical order of accuracy.
    pub order: usize,
    /// Nodes c_i.
    pub c: &'static [f64],
    /// Strictly lower triangular a_ij, row i holding a_i0 … a_i(i−1).
    pub a: &'static [&'static [f64]],
    /// Weights b_i.
    pub b: &'static [f64],
}

impl Tableau {
    /// Number of stages.
    pub fn stages(&self) -> usize {
        self.b.len()
    }
}

/// The classical fourth-order method.
pub const RK4: Tableau = Tableau {
    name: "rk4",
    order: 4,
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
};

/// The eighth-order, 12-stage method of Dormand and Prince (DOP853; Hairer,
/// Nørsett & Wanner, *Solving ODEs I*, 2nd ed., §II.10), used here with fixed
/// steps and without its embedded error estimator.
pub const DOP853: Tableau = Tableau {
    name: "dop853",
    order: 8,
    c: &[
        0.0,
        0.526001519587677318785587544488e-01,
        0.789002279381515978178381316732e-01,
        0.118350341907227396726757197510,
        0.281649658092772603273242802490,
        0.333333333333333333333333333333,
        0.25,
        0.307692307692307692307692307692,
        0.651282051282051282051282051282,
        0.6,
        0.857142857142857142857142857142,
        1.0,
    ],
    a: &[
        &[],
        &[5.26001519587677318785587544488e-2],
        &[
            1.97250569845378994544595329183e-2,
            5.91751709536136983633785987549e-2,
        ],
        &[
            2.95875854768068491816892993775e-2,
            0.0,
            8.87627564304205475450678981324e-2,
        ],
        &[
            2.41365134159266685502369798665e-1,
            0.0,
            -8.84549479328286085344864962717e-1,
            9.24834003261792003115737966543e-1,
        ],
        &[
            3.7037037037037037037037037037e-2,
            0.0,
            0.0,
            1.70828608729473871279604482173e-1,
            1.25467687566822425016691814123e-1,
        ],
        &[
            3.7109375e-2,
            0.0,
            0.0,
            1.70252211019544039314978060272e-1,
            6.02165389804559606850219397283e-2,
            -1.7578125e-2,
        ],
        &[
            3.70920001185047927108779319836e-2,
            0.0,
            0.0,
            1.70383925712239993810214054705e-1,
            1.07262030446373284651809199168e-1,
            -1.53194377486244017527936158236e-2,
            8.27378916381402288758473766002e-3,
        ],
        &[
            6.24110958716075717114429577812e-1,
            0.0,
            0.0,
            -3.36089262944694129406857109825,
            -8.68219346841726006818189891453e-1,
            2.75920996994467083049415600797e1,
            2.01540675504778934086186788979e1,
            -4.34898841810699588477366255144e1,
        ],
        &[
            4.77662536438264365890433908527e-1,
            0.0,
            0.0,
            -2.48811461997166764192642586468,
            -5.90290826836842996371446475743e-1,
            2.12300514481811942347288949897e1,
            1.52792336328824235832596922938e1,
            -3.32882109689848629194453265587e1,
            -2.03312017085086261358222928593e-2,
        ],
        &[
            -9.3714243008598732571704021658e-1,
            0.0,
            0.0,
            5.18637242884406370830023853209,
            1.09143734899672957818500254654,
            -8.14978701074692612513997267357,
            -1.85200656599969598641566180701e1,
            2.27394870993505042818970056734e1,
            2.49360555267965238987089396762,
            -3.0467644718982195003823669022,
        ],
        &[
            2.27331014751653820792359768449,
            0.0,
            0.0,
            -1.05344954667372501984066689879e1,
            -2.00087205822486249909675718444,
            -1.79589318631187989172765950534e1,
            2.79488845294199600508499808837e1,
            -2.85899827713502369474065508674,
            -8.87285693353062954433549289258,
            1.23605671757943030647266201528e1,
            6.43392746015763530355970484046e-1,
        ],
    ],
    b: &[
        5.42937341165687622380535766363e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        4.45031289275240888144113950566,
        1.89151789931450038304281599044,
        -5.8012039600105847814672114227,
        3.1116436695781989440891606237e-1,
        -1.52160949662516078556178806805e-1,
        2.01365400804030348374776537501e-1,
        4.47106157277725905176885569043e-2,
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    fn check_consistency(t: &Tableau) {
        let s: f64 = t.b.iter().sum();
        assert!((s - 1.0).abs() < 1e-14, "{}: Σb = {s}", t.name);
        for (i, row) in t.a.iter().enumerate() {
            assert_eq!(row.len(), i);
            let ci: f64 = row.iter().sum();
            assert!((ci - t.c[i]).abs() < 1e-14, "{}: row {i}", t.name);
        }
    }

    #[test]
    fn tableaux_are_consistent() {
        check_consistency(&RK4);
        check_consistency(&DOP853);
    }

    /// y' = y integrated over [0, 1] in n steps: the error falls as h^order.
    #[test]
    fn orders_are_observed_on_exponential_growth() {
        for t in [RK4, DOP853] {
            let err = |steps: usize| {
                let h = 1.0 / steps as f64;
                let mut y = 1.0_f64;
                for _ in 0..steps {
                    let mut k = vec![0.0; t.stages()];
                    for i in 0..t.stages() {
                        let yi = y + h * t.a[i].iter().zip(&k).map(|(a, k)| a * k).sum::<f64>();
                        k[i] = yi;
                    }
                    y += h * t.b.iter().zip(&k).map(|(b, k)| b * k).sum::<f64>();
                }
                (y - 1f64.exp()).abs()
            };
            let (e1, e2) = (err(4), err(8));
            let observed = (e1 / e2).log2();
            assert!(
                (observed - t.order as f64).abs() < 0.5,
                "{}: order {observed}",
                t.name
            );
        }
    }
}
