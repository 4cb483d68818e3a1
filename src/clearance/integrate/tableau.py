"""Butcher tableaus as data: explicit 7-stage FSAL 5(4) pairs with a 4th-order continuous
extension, all in one layout (the integrator loop `erk.erk54` takes any of them).

  A (7, 6)  stage coefficients; row 7 is the 5th-order weights b (FSAL: stage 7 is f(y_new))
  C (7,)    nodes
  B (7,)    5th-order weights (= A[6] with b_7 = 0)
  E (7,)    error weights b - b_hat (5th minus embedded 4th order); only |E K| is used
  P (7, 4)  dense output y(t + x h) = y + h sum_k K[k] (P[k,0] x + P[k,1] x^2 + P[k,2] x^3
            + P[k,3] x^4), with sum_j P[k, j] = B[k] (the interpolant ends at y_new)

DP5: Dormand & Prince 1980; dense output of Hairer/Shampine as in scipy.integrate RK45.P.
TS5: Tsitouras 2011 (Comput. Math. Appl. 62, 770-775), values as in OrdinaryDiffEq.jl
(Tsit5ConstantCache, Tsit5Interp). Tsit5 satisfies only the first-column simplifying
assumption, so its weights were checked against all 17 rooted-tree conditions of order <= 5
(tests/test_tsit5.py; residuals ~1e-14), the embedded weights against the 8 of order <= 4
and the interpolant against those of order <= 4 for every x.
"""

import numpy as np

DP5_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
DP5_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
)
DP5_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
# error estimate: b - b_hat (5th minus 4th order weights)
DP5_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])
DP5_P = np.array(
    [
        [1, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0, 0, 0, 0],
        [0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
        [0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ]
)

TS5_C = np.array([0.0, 0.161, 0.327, 0.9, 0.9800255409045097, 1.0, 1.0])
TS5_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.161, 0.0, 0.0, 0.0, 0.0, 0.0],
        [-0.008480655492356989, 0.335480655492357, 0.0, 0.0, 0.0, 0.0],
        [2.8971530571054935, -6.359448489975075, 4.3622954328695815, 0.0, 0.0, 0.0],
        [
            5.325864828439257,
            -11.748883564062828,
            7.4955393428898365,
            -0.09249506636175525,
            0.0,
            0.0,
        ],
        [
            5.86145544294642,
            -12.92096931784711,
            8.159367898576159,
            -0.071584973281401,
            -0.028269050394068383,
            0.0,
        ],
        [
            0.09646076681806523,
            0.01,
            0.4798896504144996,
            1.379008574103742,
            -3.290069515436081,
            2.324710524099774,
        ],
    ]
)
TS5_B = np.append(TS5_A[6], 0.0)
# error estimate b - b_hat: OrdinaryDiffEq's btilde is b_hat - b (b_hat_7 = 1/66), hence the
# minus sign; the sign does not matter to the error norm
TS5_E = -np.array(
    [
        -0.00178001105222577714,
        -0.0008164344596567469,
        0.007880878010261995,
        -0.1447110071732629,
        0.5823571654525552,
        -0.45808210592918697,
        0.015151515151515152,
    ]
)
TS5_P = np.array(
    [
        [1.0, -2.763706197274826, 2.9132554618219126, -1.0530884977290216],
        [0.0, 0.13169999999999998, -0.2234, 0.1017],
        [0.0, 3.9302962368947516, -5.941033872131505, 2.490627285651253],
        [0.0, -12.411077166933676, 30.33818863028232, -16.548102889244902],
        [0.0, 37.50931341651104, -88.1789048947664, 47.37952196281928],
        [0.0, -27.896526289197286, 65.09189467479366, -34.87065786149661],
        [0.0, 1.5, -4.0, 2.5],
    ]
)
