function [L1,L2,info]=slope_lyap(funcs,point,want_l2)
%% First (and second) Lyapunov coefficient of a Hopf point of slope_funcs.m
% Kuznetsov's convention as in DDE-BIFTOOL's nmfm_hopf/nmfm_genh: right null
% vector q of Delta(i*omega) with |q|_2=1 over the whole state
% (z, m_y, s_x, s_y, u), left null vector p with p*Delta'(i*omega)*q=1,
% c1 = 1/2 p (B(phibar,h20) + 2 B(phi,h11) + C(phi,phi,phibar)), L1 = Re(c1)/omega,
% L2 = Re(c2)/omega. These formulas are DDE-BIFTOOL's (copied from
% nmfm_genh.m) with one change:
% The co-moving frame keeps the eigenvalue 0 (translation z -> z+const,
% eigenvector e_z), so Delta(0) is singular and the stock nmfm_hopf's
% Delta(0)\B(phi,phibar) is meaningless. The frequency-0 terms h11, h22
% are therefore taken as h(theta) = h0 + beta*theta*e_z, a slow drift of z
% (the mean of m_y moves with the amplitude, as c = <m_y> does on the
% orbits), which gives the bordered system
%   [Delta(0), Delta'(0)*e_z; e_z', 0] [h0; beta] = [r; 0].
% The z-part never enters B, C, D, E (z appears only linearly in eqs. 6a-6e),
% and by the translation symmetry the drift does not feed back on the Hopf
% pair, so c1, c2 are those of the system without the translation.
% info: c1, c2, omega, q, p, the m_y component of q (l1_my = L1/|q_my|^2 is
% L1 with q scaled to |q_my|=1).
if nargin<3, want_l2=false; end
omega=abs(point.omega); lambda0=1i*omega;
n=length(point.x);
Delta=@(z,order)ch_matrix(funcs,point.x,point.parameter,z,'deri',order);
[p,q,sg]=nmfm_nullvector(funcs,point,lambda0);
if sg, error('slope_lyap: singular bordered matrix for the null vectors'); end
par0=point.parameter(:)*0;
devl=@(v,lambda)nmfm_dev_fun([v;par0(:,ones(1,size(v,2)))],'lambda',lambda);
devlt=@(v,lambda,t)nmfm_dev_fun([v;par0(:,ones(1,size(v,2)))],'lambda',lambda,'t',t);
ez=zeros(n,1); ez(1)=1;
M0=[Delta(0,0),Delta(0,1)*ez; ez',0];
solve0=@(r)drift_solve(M0,r,ez,devlt);
F=nmfm_deriv_define(funcs,point,'free_pars',[]);
phi=devl(q,lambda0);
phibar=nmfm_dev_conj(phi);
Delta2=Delta(2*lambda0,0);
D2_by_B_phi_phi=Delta2\F.B(phi,phi);
h20=devl(D2_by_B_phi_phi,2*lambda0);
h11=solve0(F.B(phi,phibar));
c1=(1/2)*p*(F.B(phibar,h20)+2*F.B(phi,h11)+F.C(phi,phi,phibar));
L1=real(c1)/omega;
info=struct('c1',c1,'omega',omega,'q',q,'p',p,'q_my',q(2),'l1_my',L1/abs(q(2))^2,...
    'cond_M0',cond(M0));
L2=NaN;
if ~want_l2, return; end
%% second Lyapunov coefficient, nmfm_genh.m's formulas with solve0 for Delta(0)\
Delta3=Delta(3*lambda0,0);
DDelta2=Delta(2*lambda0,1);
h20bar=nmfm_dev_conj(h20);
h30=devl(Delta3\(3*F.B(phi,h20)+F.C(phi,phi,phi)),3*lambda0);
h21=nmfm_binv(funcs,point,lambda0,q,p,...
    F.B(phibar,h20)+2*F.B(phi,h11)+F.C(phi,phi,phibar),-2*c1);
h21bar=nmfm_dev_conj(h21);
h31_v1=Delta2\(F.B(phibar,h30)+3*F.B(phi,h21)+3*F.B(h20,h11)+...
    3*F.C(phi,phibar,h20)+3*F.C(phi,phi,h11)+F.D(phi,phi,phi,phibar));
h31_v20=-6*c1*(Delta2\(DDelta2*D2_by_B_phi_phi));
h31_v21=6*c1*D2_by_B_phi_phi;
h31=devlt([h31_v1,h31_v20,h31_v21],2*lambda0*[1,1,1],[0,0,1]);
h22=solve0(2*F.B(phibar,h21)+2*F.B(h11,h11)+2*F.B(phi,h21bar)+F.B(h20,h20bar)+...
    F.C(phibar,phibar,h20)+F.C(phi,phi,h20bar)+4*F.C(phi,phibar,h11)+...
    F.D(phi,phi,phibar,phibar));
c2=(1/12)*p*(6*F.B(h11,h21)+3*F.B(h21bar,h20)+F.B(h20bar,h30)+3*F.B(phi,h22)+...
    2*F.B(phibar,h31)+6*F.C(phibar,h20,h11)+6*F.C(phi,h11,h11)+...
    3*F.C(phi,h20,h20bar)+6*F.C(phi,phibar,h21)+3*F.C(phi,phi,h21bar)+...
    F.C(phibar,phibar,h30)+6*F.D(phi,phi,phibar,h11)+3*F.D(phi,phibar,phibar,h20)+...
    F.D(phi,phi,phi,h20bar)+F.E(phi,phi,phi,phibar,phibar));
L2=real(c2)/omega;
info.c2=c2;
end

function h=drift_solve(M0,r,ez,devlt)
%% h(theta) = h0 + beta*theta*e_z from the bordered system (see above)
n=numel(ez);
hb=M0\[r;0];
h=devlt([hb(1:n),hb(n+1)*ez],[0,0],[0,1]);
end
