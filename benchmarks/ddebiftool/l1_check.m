function l1_check(tau,kstart,which,krange)
%% Independent check of slope_lyap's l1: the amplitude of the periodic orbits
% near the Hopf point. Normal form z' = (mu(k) + i omega) z + c1 z|z|^2 gives
% orbits with |z|^2 = -mu'(k_H) (k-k_H) / Re(c1), and m_y(t) = 2 Re(z q_my e^{i omega t})
% + O(|z|^2), so the first Fourier amplitude a1 of m_y on DDE-BIFTOOL's
% collocated orbits gives
%   l1_est = Re(c1)/omega = -4 |q_my|^2 mu' (k-k_H) / (omega a1^2),  error O(k-k_H).
% mu' = d Re(lambda)/dk comes from Delta(i omega) at equilibria corrected at
% k_H +- h (dlambda/dk = -p dDelta/dk q with p Delta' q = 1). Only the
% normalisation |q| = 1 is shared with slope_lyap; the nonlinear terms are
% not used. which, krange: which Hopf crossing of the sweep in k (hopf_point.m).
if nargin<3, which=1; end
if nargin<4, krange=3; end
setup_path(); addpath(fullfile(getenv('DDEBIFTOOL'),'ddebiftool_extra_nmfm'));
t0=tic;
[hopf,stbr,funcs,ip,hbr]=hopf_point(tau,kstart,true,which,krange);
funcs.sys_mfderi=@slope_mfderi;
[L1,~,info]=slope_lyap(funcs,hopf);
kH=hopf.parameter(ip.k); om=info.omega; q=info.q; p=info.p;
%% mu' by central differences in k (equilibrium re-corrected at each k)
h=1e-4*kH; D=cell(1,2); sgn=[1,-1];
for i=1:2
    st=stbr.point(1); st.x=hopf.x; st.parameter=hopf.parameter;
    st.parameter(ip.k)=kH+sgn(i)*h;
    mth=stbr.method.point; mth.extra_condition=1;
    [st,ok]=p_correc(funcs,st,ip.c,[],mth);
    if ~ok, error('equilibrium correction failed'); end
    D{i}=ch_matrix(funcs,st.x,st.parameter,1i*om);
end
dlam=-p*(D{1}-D{2})/(2*h)*q; mup=real(dlam);
fprintf('L1CHECK tau=%g k_H=%.8f omega=%.8f l1(normal form)=%.8e mu''=%.6e |q_my|=%.6f\n',...
    tau,kH,om,L1,mup,abs(q(2)));
%% small orbits from the Hopf point
[pbr,suc]=SetupPsol(funcs,hbr,1,'contpar',[ip.k,ip.c],'degree',4,'intervals',40,...
    'radius',1e-4);
if ~suc, error('psol init failed'); end
pbr.method.continuation.plot=0;
pbr.method.point.extra_condition=1;
pbr.method.point.adapt_mesh_after_correct=1;
pbr.method.point.adapt_mesh_before_correct=1;
pbr.method.continuation.steplength_growth_factor=1.5;
pbr.parameter.max_step=[ip.k,2e-3*kH];
pbr=br_contn(funcs,pbr,14);
s=linspace(0,1,1025); s=s(1:end-1);
dk=[]; est=[];
for j=2:numel(pbr.point)
    pt=pbr.point(j);
    my=psol_eva(pt.profile,pt.mesh,s,pt.degree); my=my(2,:);
    a1=2*abs(mean(my.*exp(-2i*pi*s)));
    dk(end+1)=pt.parameter(ip.k)-kH; %#ok<AGROW>
    est(end+1)=-4*abs(q(2))^2*mup*dk(end)/(om*a1^2); %#ok<AGROW>
    fprintf('L1CHECK   k-k_H=%+.3e a1(m_y)=%.4e l1_est=%.6e\n',dk(end),a1,est(end));
end
% l1_est = l1 + O(k-k_H): extrapolate with a straight line through the 6 smallest
% |k-k_H| >= 1e-5; below that the corrector's tolerance on k is a visible
% part of k-k_H (at tau=2 the first orbit, k-k_H=2e-7, is 2.4e-3 off the rest)
use=find(abs(dk)>=1e-5); [~,o]=sort(abs(dk(use))); o=use(o(1:min(6,numel(o))));
cf=polyfit(dk(o),est(o),1);
fprintf('L1CHECK tau=%g l1 from amplitudes (k-k_H -> 0)=%.6e, normal form %.6e, rel.diff %.1e, orbits on the %s side (%s)  %.0fs\n',...
    tau,cf(2),L1,abs(cf(2)/L1-1),ifelse(mean(dk)>0,'k>k_H','k<k_H'),...
    ifelse(sign(mup*mean(dk))>0,'where the crossing pair has Re(lambda) > 0: supercritical',...
    'where the crossing pair has Re(lambda) < 0: subcritical'),toc(t0));
end
function r=ifelse(c,a,b)
if c, r=a; else, r=b; end
end
